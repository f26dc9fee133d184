// readFinestLevel: the DEM's samples gathered from a pyramid's finest-level patches into one
// row-major array, for the methods that hold the whole raster in memory instead of
// streaming it (the RTIN yardstick, Lee & Shin 2011's GPU quadtree).
#pragma once

#include "terrain/base/Result.h"

#include <vector>

namespace terrain::io {
class PyramidReader;
}

namespace terrain::runtime {

/// width × height samples of the raster (the layout's), row-major, rows running south. The
/// caller checks its memory budget before calling: this reads every finest patch.
Result<std::vector<float>> readFinestLevel(io::PyramidReader& reader);

}  // namespace terrain::runtime
