// A resampled source's own samples against the pyramid (issue 21): a rotated grid is built
// from GDAL's bilinear resampling of it, but the bound Err(P) must hold for the samples the
// user gave, which lie between the resampled grid's samples. The builder raises Err(P) to
// the largest distance measured here and terrain-inspect --verify --source measures it
// again, the same way: each sample against the surface of the patch holding it at its
// place, whichever diagonal the tessellator draws (as for on-grid samples,
// PyramidSourceCheck.h).
#pragma once

#include "terrain/base/Result.h"
#include "terrain/source/DemReader.h"
#include "terrain/pyramid/PatchRecord.h"
#include "terrain/pyramid/PyramidLayout.h"

#include <cstdint>
#include <functional>

namespace terrain::io::detail {

/// The larger distance from `height` to the two surfaces (one per diagonal) the patch's
/// cell at (u, v) can have, (u, v) in level samples from the patch's north-west sample
/// (0 … quads each; the last row and column belong to the last cell). `tileSamples`: the
/// record's row length, apron included.
double distanceToPatchSurface(const PatchRecord& patch, int tileSamples, int quads, double u,
                              double v, double height);

/// Visits every valid sample of `original` (the source on its own grid, placed on the
/// pyramid's raster by `grid`) that lies in patch rows [firstPatchRow, firstPatchRow +
/// patchRows) of `level`: `patchAt(px, py)` gives that patch, `visit` the sample's stored
/// column and row and its largest distance to the patch's surface there. Reads only the
/// source rows that cross those patch rows. Calling thread.
Status visitOriginalSamples(
    DemReader& original, const ResampledGrid& grid, const PyramidLayout& layout, int level,
    std::int64_t firstPatchRow, std::int64_t patchRows,
    const std::function<const PatchRecord&(std::int64_t px, std::int64_t py)>& patchAt,
    const std::function<void(const PatchRecord& patch, std::int64_t column, std::int64_t row,
                             double distance)>& visit);

}  // namespace terrain::io::detail
