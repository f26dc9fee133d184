// NativeGrids: the data of native leaves (docs/globe.md, "Native leaves"). A globe pyramid's
// face grids resample its sources, so its finest level cuts across their triangles and
// differs from them by its Err(P), which no LOD over the face grid can remove near the ground.
// A source's own longitude/latitude grid does not: each one is written, as the composite
// shows it at its own samples, as a planar pyramid inside the globe pyramid
// (ManifestGlobeSource::native), which the runtime draws on the ellipsoid in place of the
// finest face patches it covers.
//
// The grid is the source's, grown by a margin of a patch's width (in its samples) on every
// side that is an edge (not past a pole, not across the longitudes of a grid around the whole
// Earth), so that a finest face patch reaching past the source's edge still lies on it. At a sample
// the composite shows the source, the value is the source's own (feathered where it is blended into
// a coarser one at its edge, as the face grids take it); at a filled void its fill; elsewhere
// (under a finer source, in the margin) the composite's surface there.
#pragma once

#include "GlobeSources.h"
#include "RowFill.h"
#include "terrain/base/Result.h"
#include "terrain/build/PyramidBuilder.h"

#include <filesystem>
#include <string>
#include <vector>

namespace terrain::io::detail {

/// Builds the native grid of every source of `composite` that is a longitude/latitude grid
/// of its own (a projected source's samples are not on its grid: none for it) into
/// `pyramidFolder`/native/<k>, k its index finest first, grown by the quads of a patch of
/// `options` (a finest face patch is no wider than that many of its source's samples near
/// the source's centre, so one reaching past the edge still lies on the grid); returns each
/// source's folder (ManifestGlobeSource::native, empty where none), in the composite's order.
Result<std::vector<std::string>> buildNativeGrids(const GlobeSources& composite,
                                                  const std::filesystem::path& pyramidFolder,
                                                  const PyramidBuildOptions& options);

/// The native grid of a region build's one source (GlobeShardTiling.cpp): the same grid, read
/// from `source` window by window (filled as `voids` fill it) and built by shards within
/// `options`' memory, into `pyramidFolder`/native/0; returns that folder.
Result<std::string> buildNativeGridByShards(DemReader& source, SourceVoids& voids,
                                            const GeographicGrid& grid,
                                            const std::filesystem::path& pyramidFolder,
                                            const PyramidBuildOptions& options);

}  // namespace terrain::io::detail
