// The source's band for terrain-inspect --verify --source (see SourceBand.h).
#include "SourceBand.h"

#include <fmt/format.h>

namespace terrain::inspect {

Result<std::optional<int>> sourceBand(const io::ManifestSource& built, std::optional<int> given,
                                      const std::string& pyramid) {
    if (given && *given != built.band) {
        const std::string inputs =
            built.inputs.empty() ? std::string("its source")
            : built.inputs.size() == 1
                ? built.inputs.front()
                : fmt::format("{} and {} more", built.inputs.front(), built.inputs.size() - 1);
        return Error{fmt::format(
            "{}: was built from band {} (of {}) of {}, as its manifest's source.band says; "
            "-b {} would check it against band {}: leave out -b/--band or give -b {}",
            pyramid, built.band, built.bandCount, inputs, *given, *given, built.band)};
    }
    if (given) return given;
    // A manifest without a band read band 1 (PyramidManifest.h); left unset, the source
    // opens through the reader the build chose for it.
    if (built.band == 1) return std::optional<int>{};
    return std::optional<int>{built.band};
}

}  // namespace terrain::inspect
