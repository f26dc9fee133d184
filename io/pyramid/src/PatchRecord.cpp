// PatchRecord: the per-patch summary of its drawn samples, one loop for every writer.
#include "terrain/pyramid/PatchRecord.h"

#include "terrain/base/Assert.h"

#include <algorithm>
#include <limits>

namespace terrain::io {

void summariseDrawnSamples(const PyramidLayout& layout, std::span<const float> heights,
                           std::span<const std::uint8_t> valid, PatchInfo& info) {
    const auto tile = static_cast<std::size_t>(layout.tileSamples());
    const auto n = static_cast<std::size_t>(layout.patchSamples());
    TERRAIN_ASSERT(heights.size() == tile * tile, "summariseDrawnSamples: heights size");
    TERRAIN_ASSERT(valid.empty() || valid.size() == tile * tile,
                   "summariseDrawnSamples: mask size");
    float lo = std::numeric_limits<float>::infinity(), hi = -lo;
    std::uint32_t noData = 0;
    for (std::size_t j = 1; j <= n; ++j) {
        for (std::size_t i = j * tile + 1; i <= j * tile + n; ++i) {
            lo = std::min(lo, heights[i]);
            hi = std::max(hi, heights[i]);
            if (!valid.empty()) noData += valid[i] == 0 ? 1u : 0u;
        }
    }
    info.minHeight = lo;
    info.maxHeight = hi;
    info.noDataSamples = noData;
}

}  // namespace terrain::io
