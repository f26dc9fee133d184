// BoundaryArtefacts: one pass over the pixels, each checked along its row and its column.
#include "terrain/runtime/BoundaryArtefacts.h"

#include "terrain/base/Assert.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace terrain::runtime {
namespace {

/// Whether pixels i and j (of images a and b) differ by more than `threshold` in R, G or B.
bool differ(std::span<const std::uint8_t> a, std::size_t i, std::span<const std::uint8_t> b,
            std::size_t j, int threshold) {
    for (std::size_t c = 0; c < 3; ++c)
        if (std::abs(int{a[4 * i + c]} - int{b[4 * j + c]}) > threshold) return true;
    return false;
}

}  // namespace

std::vector<std::uint32_t> patchIdsOf(std::span<const std::uint8_t> patchViewRgba) {
    TERRAIN_ASSERT(patchViewRgba.size() % 4 == 0, "patchIdsOf: not RGBA8");
    std::vector<std::uint32_t> ids(patchViewRgba.size() / 4);
    for (std::size_t i = 0; i < ids.size(); ++i) {
        ids[i] = std::uint32_t{patchViewRgba[4 * i]} |
                 std::uint32_t{patchViewRgba[4 * i + 1]} << 8 |
                 std::uint32_t{patchViewRgba[4 * i + 2]} << 16;
    }
    return ids;
}

BoundaryArtefacts findBoundaryArtefacts(const FrameImages& lod,
                                        std::span<const std::uint32_t> patchIds,
                                        const FrameImages& reference, int thresholdLevels) {
    const std::size_t w = static_cast<std::size_t>(lod.width);
    const std::size_t pixels = lod.pixels();
    TERRAIN_ASSERT(lod.width == reference.width && lod.height == reference.height &&
                       lod.rgba.size() == 4 * pixels && reference.rgba.size() == 4 * pixels &&
                       lod.depth.size() == pixels && reference.depth.size() == pixels &&
                       patchIds.size() == pixels,
                   "findBoundaryArtefacts: sizes differ");
    const std::span<const std::uint8_t> colour(lod.rgba);
    BoundaryArtefacts result;
    for (std::size_t i = 0; i < pixels; ++i) {
        const std::size_t x = i % w;
        const bool hasLeft = x > 0, hasRight = x + 1 < w;
        const bool hasBelow = i >= w, hasAbove = i + w < pixels;
        const std::uint32_t id = patchIds[i];
        const bool onBoundary =
            (hasLeft && patchIds[i - 1] != id) || (hasRight && patchIds[i + 1] != id) ||
            (hasBelow && patchIds[i - w] != id) || (hasAbove && patchIds[i + w] != id);
        if (!onBoundary) continue;
        ++result.boundaryPixels;
        if (!differ(colour, i, reference.rgba, i, thresholdLevels)) continue;
        const double depth = lod.depth[i], referenceDepth = reference.depth[i];
        const bool referenceSurface =
            std::abs(depth - referenceDepth) <=
            BoundaryArtefacts::kSameSurface * std::max(depth, referenceDepth);
        // Along a line (a, i, b) that crosses a boundary at i: i stands out from both sides.
        // A wrongly shaded edge pixel stands out where both sides are right: where they differ
        // from the reference too, the LOD's own detail differs (a coarser level's shading,
        // aliasing), which is not the boundary's doing.
        const auto standsOut = [&](std::size_t a, std::size_t b) {
            const bool sliver = patchIds[a] != id && patchIds[b] != id;
            const bool edge = !sliver && (patchIds[a] != id || patchIds[b] != id) &&
                              referenceSurface &&
                              !differ(colour, a, reference.rgba, a, thresholdLevels) &&
                              !differ(colour, b, reference.rgba, b, thresholdLevels);
            return (sliver || edge) && differ(colour, i, colour, a, thresholdLevels) &&
                   differ(colour, i, colour, b, thresholdLevels);
        };
        if ((hasLeft && hasRight && standsOut(i - 1, i + 1)) ||
            (hasBelow && hasAbove && standsOut(i - w, i + w)))
            result.pixels.push_back(i);
    }
    return result;
}

}  // namespace terrain::runtime
