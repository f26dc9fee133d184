// BoundaryShading: one pass over the pixels, each paired with its right and upper neighbour.
#include "terrain/runtime/BoundaryShading.h"

#include "PatchBoundaryImages.h"

#include <algorithm>
#include <cmath>

namespace terrain::runtime {
namespace {

double luma(std::span<const std::uint8_t> rgba, std::size_t i) {
    return 0.299 * rgba[4 * i] + 0.587 * rgba[4 * i + 1] + 0.114 * rgba[4 * i + 2];
}

}  // namespace

BoundaryShading measureBoundaryShading(const FrameImages& lod,
                                       std::span<const std::uint32_t> patchIds,
                                       const FrameImages& reference) {
    detail::assertSameFrame(lod, patchIds, reference);
    const std::size_t w = static_cast<std::size_t>(lod.width);
    const std::size_t pixels = lod.pixels();
    const auto compared = [&](std::size_t i) {
        return patchIds[i] != 0 && lod.drawn(i) && reference.drawn(i) &&
               detail::onReferenceSurface(lod, reference, i);
    };
    BoundaryShading result;
    double boundarySum = 0.0, interiorSum = 0.0;
    const auto pair = [&](std::size_t a, std::size_t b) {
        if (!compared(a) || !compared(b)) return;
        const double lodStep = std::abs(luma(lod.rgba, a) - luma(lod.rgba, b));
        const double referenceStep = std::abs(luma(reference.rgba, a) - luma(reference.rgba, b));
        const double excess = std::max(0.0, lodStep - referenceStep);
        if (patchIds[a] != patchIds[b]) {
            ++result.boundaryPairs;
            boundarySum += excess;
        } else {
            ++result.interiorPairs;
            interiorSum += excess;
        }
    };
    for (std::size_t i = 0; i < pixels; ++i) {
        if (i % w + 1 < w) pair(i, i + 1);
        if (i + w < pixels) pair(i, i + w);
    }
    if (result.boundaryPairs > 0) result.boundaryExcessLevels = boundarySum / double(result.boundaryPairs);
    if (result.interiorPairs > 0) result.interiorExcessLevels = interiorSum / double(result.interiorPairs);
    return result;
}

}  // namespace terrain::runtime
