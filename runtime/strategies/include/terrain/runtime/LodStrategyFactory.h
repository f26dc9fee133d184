// openLodStrategy: any LodMethod over one pyramid, for programs that let the user choose
// (--method, --methods). The quadtree methods open a TerrainSession; the others their own
// strategy. A method that cannot draw the pyramid (a globe, a raster too large for it) is an
// error that names the method and the pyramid.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/runtime/LodStrategy.h"
#include "terrain/runtime/TerrainSession.h"

#include <filesystem>
#include <memory>

namespace terrain::runtime {

/// Opens `options.method` over `pyramid`; `options.lod.errorPx` is the method's threshold.
Result<std::unique_ptr<LodStrategy>> openLodStrategy(const std::filesystem::path& pyramid,
                                                     const TerrainSessionOptions& options);

}  // namespace terrain::runtime
