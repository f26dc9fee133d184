// BoundaryArtefacts: one pass over the pixels, each checked along its row and its column.
#include "terrain/runtime/BoundaryArtefacts.h"

#include "PatchBoundaryImages.h"
#include "terrain/base/Assert.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
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

/// Whether pixel i of a depth image `w` pixels wide lies on a silhouette
/// (BoundaryArtefacts::kSilhouetteCurvature): its depth bends sharply along its row or its
/// column, or it draws something next to a pixel that draws nothing, or the other way.
bool onSilhouette(std::span<const float> depth, std::size_t w, std::size_t i) {
    const std::size_t x = i % w;
    const double d = depth[i];
    const auto empty = [&](std::size_t n) { return (depth[n] > 0.0f) != (d > 0.0); };
    const auto bends = [&](std::size_t a, std::size_t b) {
        return empty(a) || empty(b) ||
               std::abs(double(depth[a]) - 2.0 * d + double(depth[b])) >
                   BoundaryArtefacts::kSilhouetteCurvature * d;
    };
    const bool hasLeft = x > 0, hasRight = x + 1 < w;
    const bool hasBelow = i >= w, hasAbove = i + w < depth.size();
    if (hasLeft && hasRight && bends(i - 1, i + 1)) return true;
    if (hasBelow && hasAbove && bends(i - w, i + w)) return true;
    // At the image's border only the one-sided test of a drawn pixel beside an empty one.
    return (hasLeft && empty(i - 1)) || (hasRight && empty(i + 1)) || (hasBelow && empty(i - w)) ||
           (hasAbove && empty(i + w));
}

/// Whether a silhouette of `lod` or `reference` lies within `radius` pixels of pixel i
/// (rows and columns).
bool nearSilhouette(const FrameImages& lod, const FrameImages& reference, std::size_t i,
                    int radius) {
    const auto w = static_cast<std::ptrdiff_t>(lod.width);
    const auto h = static_cast<std::ptrdiff_t>(lod.height);
    const auto x0 = static_cast<std::ptrdiff_t>(i) % w, y0 = static_cast<std::ptrdiff_t>(i) / w;
    const auto width = static_cast<std::size_t>(w);
    for (std::ptrdiff_t y = std::max<std::ptrdiff_t>(0, y0 - radius);
         y <= std::min(h - 1, y0 + radius); ++y) {
        for (std::ptrdiff_t x = std::max<std::ptrdiff_t>(0, x0 - radius);
             x <= std::min(w - 1, x0 + radius); ++x) {
            const auto q = static_cast<std::size_t>(y * w + x);
            if (onSilhouette(lod.depth, width, q) || onSilhouette(reference.depth, width, q))
                return true;
        }
    }
    return false;
}

/// What a boundary pixel is, seen along one line across the boundary.
enum class Standing { Blends, Artefact, AtSilhouette };

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

bool onPatchBoundary(std::span<const std::uint32_t> patchIds, int width, std::size_t i) {
    const auto w = static_cast<std::size_t>(width);
    const std::uint32_t id = patchIds[i];
    return (i % w > 0 && patchIds[i - 1] != id) || (i % w + 1 < w && patchIds[i + 1] != id) ||
           (i >= w && patchIds[i - w] != id) || (i + w < patchIds.size() && patchIds[i + w] != id);
}

BoundaryArtefacts findBoundaryArtefacts(const FrameImages& lod,
                                        std::span<const std::uint32_t> patchIds,
                                        const FrameImages& reference, int shiftPx,
                                        int thresholdLevels) {
    detail::assertSameFrame(lod, patchIds, reference);
    const std::size_t w = static_cast<std::size_t>(lod.width);
    const std::size_t pixels = lod.pixels();
    const std::span<const std::uint8_t> colour(lod.rgba);
    BoundaryArtefacts result;
    for (std::size_t i = 0; i < pixels; ++i) {
        const std::size_t x = i % w;
        const bool hasLeft = x > 0, hasRight = x + 1 < w;
        const bool hasBelow = i >= w, hasAbove = i + w < pixels;
        const std::uint32_t id = patchIds[i];
        if (!onPatchBoundary(patchIds, lod.width, i)) continue;
        ++result.boundaryPixels;
        if (!differ(colour, i, reference.rgba, i, thresholdLevels)) continue;
        const bool referenceSurface = detail::onReferenceSurface(lod, reference, i);
        // Whether the reference shows i's colour within shiftPx of it (the LOD may draw a
        // surface that far off).
        const auto referenceShowsNearby = [&] {
            const auto x0 = static_cast<std::ptrdiff_t>(x), y0 = static_cast<std::ptrdiff_t>(i / w);
            const auto width = static_cast<std::ptrdiff_t>(w);
            const auto height = static_cast<std::ptrdiff_t>(pixels / w);
            for (std::ptrdiff_t y = std::max<std::ptrdiff_t>(0, y0 - shiftPx);
                 y <= std::min(height - 1, y0 + shiftPx); ++y)
                for (std::ptrdiff_t xx = std::max<std::ptrdiff_t>(0, x0 - shiftPx);
                     xx <= std::min(width - 1, x0 + shiftPx); ++xx)
                    if (!differ(colour, i, reference.rgba, static_cast<std::size_t>(y * width + xx),
                                thresholdLevels))
                        return true;
            return false;
        };
        // Along a line (a, i, b) that crosses a boundary at i: i stands out from both sides.
        // A wrongly shaded edge pixel stands out where both sides are right: where they differ
        // from the reference too, the LOD's own detail differs (a coarser level's shading,
        // aliasing), which is not the boundary's doing.
        const auto standsOut = [&](std::size_t a, std::size_t b) {
            // A gap shows what lies behind both sides; a pixel of a third patch between a
            // nearer and a farther one is a silhouette's layers.
            const auto fartherThan = [&](std::size_t n) {
                return double(lod.depth[i]) <
                       double(lod.depth[n]) * (1.0 - BoundaryArtefacts::kSameSurface);
            };
            const bool sliver =
                patchIds[a] != id && patchIds[b] != id && fartherThan(a) && fartherThan(b);
            const bool edge = !sliver && (patchIds[a] != id || patchIds[b] != id) &&
                              referenceSurface &&
                              !differ(colour, a, reference.rgba, a, thresholdLevels) &&
                              !differ(colour, b, reference.rgba, b, thresholdLevels);
            if (!(sliver || edge) || !differ(colour, i, colour, a, thresholdLevels) ||
                !differ(colour, i, colour, b, thresholdLevels) || referenceShowsNearby())
                return Standing::Blends;
            // An edge pixel at a silhouette shows what the LOD's own error puts there.
            if (edge && nearSilhouette(lod, reference, i, std::max(1, shiftPx)))
                return Standing::AtSilhouette;
            return Standing::Artefact;
        };
        const Standing row = hasLeft && hasRight ? standsOut(i - 1, i + 1) : Standing::Blends;
        const Standing column = row != Standing::Artefact && hasBelow && hasAbove
                                    ? standsOut(i - w, i + w)
                                    : Standing::Blends;
        if (row == Standing::Artefact || column == Standing::Artefact)
            result.pixels.push_back(i);
        else if (row == Standing::AtSilhouette || column == Standing::AtSilhouette)
            ++result.silhouettePixels;
    }
    return result;
}

}  // namespace terrain::runtime
