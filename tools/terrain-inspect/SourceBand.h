// Which band of its source terrain-inspect --verify --source reads: the one the pyramid was
// built from (the manifest's source.band), so a pyramid built with -b 2 is checked against
// band 2, not band 1 (issue 52); a -b that names another is refused, naming both.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/pyramid/PyramidManifest.h"

#include <optional>
#include <string>

namespace terrain::inspect {

/// The band to open the source with: `given` (-b) when it is the manifest's band, else the
/// manifest's band when it is not band 1; nothing when both say band 1 by default (the
/// source opens as the build opened it). A `given` band other than the manifest's is an
/// Error naming the pyramid and both bands.
Result<std::optional<int>> sourceBand(const io::ManifestSource& built, std::optional<int> given,
                                      const std::string& pyramid);

}  // namespace terrain::inspect
