#include "terrain/pyramid/BlockHeightRanges.h"

#include "terrain/base/Assert.h"

#include <algorithm>
#include <cmath>

namespace terrain::io {

void blockHeightRanges(const GridView& patch, int blockQuads, HeightRange patchRange,
                       std::span<HeightRange> out) {
    TERRAIN_ASSERT(blockQuads >= 1 && (patch.side - 1) % blockQuads == 0);
    const int blocksPerSide = (patch.side - 1) / blockQuads;
    TERRAIN_ASSERT(out.size() == static_cast<std::size_t>(blocksPerSide) * blocksPerSide);
    for (int by = 0; by < blocksPerSide; ++by) {
        for (int bx = 0; bx < blocksPerSide; ++bx) {
            float low = patchRange.high, high = patchRange.low;
            for (int y = by * blockQuads; y <= (by + 1) * blockQuads; ++y) {
                for (int x = bx * blockQuads; x <= (bx + 1) * blockQuads; ++x) {
                    const float h = patch.at(x, y);
                    // A no-data sample's height is whatever the mask hides; the patch's
                    // range is what its info vouches for.
                    if (!std::isfinite(h)) continue;
                    low = std::min(low, std::max(h, patchRange.low));
                    high = std::max(high, std::min(h, patchRange.high));
                }
            }
            out[static_cast<std::size_t>(by) * blocksPerSide + bx] =
                low <= high ? HeightRange{low, high} : patchRange;
        }
    }
}

SampleRises sampleRises(const GridView& tile) {
    SampleRises rises;
    for (int y = 0; y < tile.side; ++y) {
        for (int x = 0; x < tile.side; ++x) {
            const float h = tile.at(x, y);
            if (x + 1 < tile.side) {
                const float rise = std::abs(tile.at(x + 1, y) - h);
                if (std::isfinite(rise)) rises.east = std::max(rises.east, rise);
            }
            if (y + 1 < tile.side) {
                const float rise = std::abs(tile.at(x, y + 1) - h);
                if (std::isfinite(rise)) rises.north = std::max(rises.north, rise);
            }
        }
    }
    return rises;
}

}  // namespace terrain::io
