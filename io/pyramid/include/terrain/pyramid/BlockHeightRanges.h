// BlockHeightRanges: the heights each tessellation block of a patch spans, so that the draw
// bounds a block's error over the block's own box rather than over its patch's whole height
// range (issue 51: a low block of a mountain patch was projected as if it reached the peak).
#pragma once

#include "terrain/pyramid/PatchErrors.h"

#include <span>

namespace terrain::io {

struct HeightRange {
    float low = 0.0f, high = 0.0f;
};

/// For every block of `patch` (row-major, blocksPerSide² = ((patch.side − 1) / blockQuads)²
/// entries in `out`): the lowest and highest of its (blockQuads + 1)² samples, kept within
/// `patchRange` (the patch's own, PatchInfo's minHeight and maxHeight). A block with no finite
/// sample in that range takes the patch's. The full-resolution surface between the samples
/// lies within their range (its triangles interpolate them), so a box over this range holds
/// the block's drawn surface as the patch's range does.
void blockHeightRanges(const GridView& patch, int blockQuads, HeightRange patchRange,
                       std::span<HeightRange> out);

/// The steepest rises of a tile's samples, metres: the largest |difference| between a
/// sample and the next along a row (east, on a longitude/latitude grid) and along a column
/// (north). With the cells' sides they bound the slopes of every triangle drawn between the
/// samples, simplified or not (globe::geographicTriangleErrorBound). Pairs with a non-finite
/// sample are skipped.
struct SampleRises {
    float east = 0.0f;
    float north = 0.0f;
};
SampleRises sampleRises(const GridView& tile);

}  // namespace terrain::io
