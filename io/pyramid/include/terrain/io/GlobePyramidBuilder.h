// GlobePyramidBuilder: builds a geographic DEM into a globe pyramid (format version 3,
// docs/pyramid-format.md, "Globe pyramids"): the source is resampled onto the cube-sphere's
// face grids (terrain::globe) at every level, down to the finest level whose grid is as fine
// as the source where it lies. Only patches that touch the source exist (plus the six face
// roots, so the LOD always has somewhere to start); elsewhere the runtime draws the bare
// ellipsoid. Err(P) is measured, not modelled: for every valid source sample, the distance
// along its ellipsoid normal to the patch's drawn triangles, both diagonals
// (GlobePatchSurface), maxed with the children's so it never grows with depth.
//
// Not yet: several sources composited into one pyramid, and sources bigger than memory (the
// source is read whole; the build refuses what exceeds the memory budget).
#pragma once

#include "terrain/base/Result.h"
#include "terrain/io/DemReader.h"
#include "terrain/io/PyramidBuilder.h"

#include <filesystem>

namespace terrain::io {

/// The finest face level for a source whose samples are `spacingMetres` apart around the
/// unit direction `where`: the coarsest level whose face grid there is at least as fine.
int globeFinestLevelFor(double spacingMetres, double latitudeDeg, double longitudeDeg, int quads);

/// Builds the globe pyramid of the geographic `reader` at `output`, through a ".partial"
/// folder renamed into place when complete (like buildPyramid). Errors name the file and the
/// problem: a source that is not geographic, or too big for the memory budget.
Result<PyramidBuildSummary> buildGlobePyramid(DemReader& reader,
                                              const std::filesystem::path& output,
                                              const PyramidBuildOptions& options = {});

}  // namespace terrain::io
