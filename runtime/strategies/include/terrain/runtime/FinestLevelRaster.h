// readFinestLevel: the DEM's samples gathered from a pyramid's finest-level patches into one
// row-major array, for the methods that hold the whole raster in memory instead of
// streaming it (the RTIN yardstick, Lee & Shin 2011's GPU quadtree, Ripolles et al.).
#pragma once

#include "terrain/base/Result.h"
#include "terrain/pyramid/PyramidReader.h"

#include <filesystem>
#include <string_view>
#include <vector>

namespace terrain::runtime {

/// Opens `pyramid` for one of those methods, refusing a globe pyramid with an error that
/// names the pyramid and `method` (e.g. "the RTIN yardstick").
Result<io::PyramidReader> openPlanarPyramid(const std::filesystem::path& pyramid,
                                            std::string_view method);

/// width × height samples of the raster (the layout's), row-major, rows running south. The
/// caller checks its memory budget before calling: this reads every finest patch.
Result<std::vector<float>> readFinestLevel(io::PyramidReader& reader);

}  // namespace terrain::runtime
