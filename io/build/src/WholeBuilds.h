// WholeBuilds: a pyramid built in one pass over sources held or streamed whole, the way
// buildPyramid (BuildBudget.cpp) takes when the budget allows: planar (PyramidBuilder.cpp,
// streaming bands across the raster) and globe (GlobePyramidBuilder.cpp, the sources held
// whole). The other way is PyramidShards.h.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/build/PyramidBuilder.h"
#include "terrain/source/DemReader.h"

#include <filesystem>
#include <span>

namespace terrain::io::detail {

Result<PyramidBuildSummary> buildWholePlanarPyramid(DemReader& reader,
                                                    const std::filesystem::path& output,
                                                    const PyramidBuildOptions& options);

Result<PyramidBuildSummary> buildWholeGlobePyramid(std::span<DemReader* const> readers,
                                                   const std::filesystem::path& output,
                                                   const PyramidBuildOptions& options);

}  // namespace terrain::io::detail
