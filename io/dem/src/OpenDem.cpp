// openDem: picks the reader for the inputs. "procedural:" is the built-in terrain, .hgt
// the SRTM reader, image extensions OpenImageIO, anything else (netCDF, VRT, DTED, ...)
// and every mosaic GDAL.
#include "DemReaderFactories.h"

#include <fmt/format.h>

#include <array>
#include <string_view>

namespace terrain::io {

namespace {

constexpr std::string_view kProceduralPrefix = "procedural:";
constexpr std::array<std::string_view, 7> kOiioExtensions = {".tif", ".tiff", ".png", ".exr",
                                                             ".jpg", ".jpeg", ".jpe"};

bool isProcedural(const std::string& input) { return input.starts_with(kProceduralPrefix); }

}  // namespace

Result<std::unique_ptr<DemReader>> openDem(const std::vector<std::string>& inputs,
                                           const DemOpenOptions& options) {
    if (inputs.empty()) return Error{"openDem: no input given"};
    if (inputs.size() > 1) {
        for (const std::string& input : inputs)
            if (isProcedural(input))
                return Error{
                    fmt::format("{}: the procedural terrain cannot be part of a mosaic", input)};
        return detail::openGdalMosaic(inputs, options);
    }
    const std::string& input = inputs.front();
    if (isProcedural(input)) return detail::openProceduralDem(input, options);
    const std::string ext = detail::lowerExtension(input);
    if (ext == ".hgt") return detail::openHgtDem(input, options);
    for (const std::string_view oiio : kOiioExtensions)
        if (ext == oiio) return detail::openOiioDem(input, options);
    return detail::openGdalDem(input, options);
}

}  // namespace terrain::io
