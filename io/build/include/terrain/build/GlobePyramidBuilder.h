// GlobePyramidBuilder: builds a geographic DEM into a globe pyramid (format version 3,
// docs/pyramid-format.md, "Globe pyramids"): the source is resampled onto the cube-sphere's
// face grids (terrain::globe) at every level, down to the finest level whose grid is as fine
// as the source where it lies. Only patches that touch the source exist (plus the six face
// roots, so the LOD always has somewhere to start); elsewhere the runtime draws the bare
// ellipsoid. Err(P) is measured, not modelled: for every source sample the composite shows,
// the distance along its ellipsoid normal from its composite height to the patch's drawn
// triangles, both diagonals (GlobePatchSurface), maxed with the children's so it never grows
// with depth. A source resampled onto its grid (a projected DEM opened with
// DemOpenOptions::geographicGrid, a rotated one) is measured at its own samples instead,
// each placed by DemReader::placeOriginalSamples.
//
// Several sources composite into one pyramid (GlobeSources.h): where they overlap the finest
// valid sample wins, a void is filled over the sources beneath it (VoidFill.h), and a
// source is feathered into the one under it at its edge; each source makes patches exist down
// to its own finest level, so a 90 m tile over a 37 km global grid adds deep levels only
// where it lies.
//
// Each source is read whole; one geographic source too large for the memory budget is built
// shard by shard instead (PyramidShards.h, BuildWay), with the nested bound above its finest
// level. Several sources, or a projected one, that exceed the budget are refused.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/source/DemReader.h"
#include "terrain/build/PyramidBuilder.h"

#include <filesystem>
#include <span>

namespace terrain::io {

/// The finest face level for a source whose samples are `spacingMetres` apart around the
/// unit direction `where`: the coarsest level whose face grid there is at least as fine.
int globeFinestLevelFor(double spacingMetres, double latitudeDeg, double longitudeDeg, int quads);
/// How far apart a face level's samples lie around a place, metres (the larger of the two
/// directions).
double globeFaceSampleSpacing(int faceLevel, double latitudeDeg, double longitudeDeg, int quads);

/// Builds the globe pyramid of the geographic `reader` at `output`:
/// buildPyramid(PyramidSurface::Globe, {&reader}, …). Errors name the file and the problem: a
/// source that is not geographic, or too big for the memory budget.
Result<PyramidBuildSummary> buildGlobePyramid(DemReader& reader,
                                              const std::filesystem::path& output,
                                              const PyramidBuildOptions& options = {});

/// The same for several geographic sources composited (finest valid sample wins). The
/// manifest's sourceExtent is the finest source's; its statistics span every source.
Result<PyramidBuildSummary> buildGlobePyramid(std::span<DemReader* const> readers,
                                              const std::filesystem::path& output,
                                              const PyramidBuildOptions& options = {});

}  // namespace terrain::io
