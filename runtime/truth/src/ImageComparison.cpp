// ImageComparison: per-pixel loops over RGBA8 images.
#include "terrain/runtime/ImageComparison.h"

#include "terrain/base/Assert.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <vector>

namespace terrain::runtime {
namespace {

/// Mean absolute R, G, B difference of pixel `i` (byte offset 4 i).
double pixelChange(std::span<const std::uint8_t> a, std::span<const std::uint8_t> b,
                   std::size_t i) {
    int sum = 0;
    for (std::size_t c = 0; c < 3; ++c) sum += std::abs(int{a[4 * i + c]} - int{b[4 * i + c]});
    return sum / 3.0;
}

}  // namespace

ImageDifference compareImages(std::span<const std::uint8_t> a, std::span<const std::uint8_t> b) {
    TERRAIN_ASSERT(a.size() == b.size() && a.size() % 4 == 0, "compareImages: sizes differ");
    const std::size_t pixels = a.size() / 4;
    double sum = 0.0;
    for (std::size_t i = 0; i < pixels; ++i) {
        for (std::size_t c = 0; c < 3; ++c) {
            const double d = static_cast<double>(a[4 * i + c]) - static_cast<double>(b[4 * i + c]);
            sum += d * d;
        }
    }
    ImageDifference result;
    if (pixels == 0) return result;
    result.rmse = std::sqrt(sum / (3.0 * static_cast<double>(pixels)));
    result.psnrDb = result.rmse > 0.0 ? 20.0 * std::log10(255.0 / result.rmse) : kIdenticalPsnrDb;
    return result;
}

std::uint64_t countOverdrawnPixels(const FrameImages& lod, const FrameImages& reference,
                                   int shiftPx) {
    TERRAIN_ASSERT(lod.width == reference.width && lod.height == reference.height &&
                       lod.depth.size() == lod.pixels() &&
                       reference.depth.size() == reference.pixels(),
                   "countOverdrawnPixels: sizes differ");
    const auto w = static_cast<std::ptrdiff_t>(lod.width);
    const auto h = static_cast<std::ptrdiff_t>(lod.height);
    const auto at = [w](std::ptrdiff_t x, std::ptrdiff_t y) {
        return static_cast<std::size_t>(y * w + x);
    };
    // The reference's coverage grown by shiftPx: along the rows, then along the columns.
    std::vector<std::uint8_t> rows(lod.pixels(), 0), grown(lod.pixels(), 0);
    for (std::ptrdiff_t y = 0; y < h; ++y)
        for (std::ptrdiff_t x = 0; x < w; ++x)
            if (reference.drawn(at(x, y)))
                for (std::ptrdiff_t k = std::max<std::ptrdiff_t>(0, x - shiftPx);
                     k <= std::min(w - 1, x + shiftPx); ++k)
                    rows[at(k, y)] = 1;
    for (std::ptrdiff_t y = 0; y < h; ++y)
        for (std::ptrdiff_t x = 0; x < w; ++x)
            if (rows[at(x, y)] != 0)
                for (std::ptrdiff_t k = std::max<std::ptrdiff_t>(0, y - shiftPx);
                     k <= std::min(h - 1, y + shiftPx); ++k)
                    grown[at(x, k)] = 1;
    std::uint64_t overdrawn = 0;
    for (std::size_t i = 0; i < lod.pixels(); ++i)
        overdrawn += lod.drawn(i) && grown[i] == 0 ? 1 : 0;
    return overdrawn;
}

UncoveredPixels countUncoveredPixels(const FrameImages& lod, const FrameImages& reference,
                                     const std::array<std::uint8_t, 3>& clearRgb) {
    TERRAIN_ASSERT(lod.width == reference.width && lod.height == reference.height &&
                       lod.rgba.size() == 4 * lod.pixels() &&
                       reference.depth.size() == reference.pixels(),
                   "countUncoveredPixels: sizes differ");
    const std::size_t pixels = lod.pixels();
    // 0: LOD drew terrain; 1: clear in the LOD (not yet reached from the sky); 2: reached.
    std::vector<std::uint8_t> state(pixels, 0);
    std::vector<std::size_t> queue;
    for (std::size_t i = 0; i < pixels; ++i) {
        const bool clear = lod.rgba[4 * i] == clearRgb[0] && lod.rgba[4 * i + 1] == clearRgb[1] &&
                           lod.rgba[4 * i + 2] == clearRgb[2];
        if (!clear) continue;
        state[i] = 1;
        if (!reference.drawn(i)) {  // sky in both: where the flood starts
            state[i] = 2;
            queue.push_back(i);
        }
    }
    const auto w = static_cast<std::size_t>(lod.width);
    for (std::size_t next = 0; next < queue.size(); ++next) {
        const std::size_t i = queue[next];
        const std::size_t x = i % w;
        const auto visit = [&](std::size_t j) {
            if (state[j] == 1) {
                state[j] = 2;
                queue.push_back(j);
            }
        };
        if (x > 0) visit(i - 1);
        if (x + 1 < w) visit(i + 1);
        if (i >= w) visit(i - w);
        if (i + w < pixels) visit(i + w);
    }
    // A clear pixel that touches the sky only at a corner is a silhouette's notch: where a
    // silhouette drawn up to ε off the reference's runs askew to the pixel grid, a pixel of
    // it can be clear with terrain on all four sides (a DEM's edge seen along its length,
    // issue 52). One step only, not a flood: a crack one pixel wide running diagonally to
    // the silhouette still counts, all but its last pixel.
    const auto touchesSkyAtACorner = [&](std::size_t i) {
        const std::size_t x = i % w;
        const bool up = i >= w, down = i + w < pixels, left = x > 0, right = x + 1 < w;
        return (up && left && state[i - w - 1] == 2) || (up && right && state[i - w + 1] == 2) ||
               (down && left && state[i + w - 1] == 2) || (down && right && state[i + w + 1] == 2);
    };
    UncoveredPixels counts;
    for (std::size_t i = 0; i < pixels; ++i) {
        if (state[i] == 0 || !reference.drawn(i)) continue;
        ++counts.uncovered;
        if (state[i] == 1 && !touchesSkyAtACorner(i)) counts.cracks.push_back(i);
    }
    return counts;
}

double meanImageChange(std::span<const std::uint8_t> a, std::span<const std::uint8_t> b) {
    TERRAIN_ASSERT(a.size() == b.size() && a.size() % 4 == 0, "meanImageChange: sizes differ");
    const std::size_t pixels = a.size() / 4;
    if (pixels == 0) return 0.0;
    double sum = 0.0;
    for (std::size_t i = 0; i < pixels; ++i) sum += pixelChange(a, b, i);
    return sum / static_cast<double>(pixels);
}

LodSwitchChange lodSwitchChange(const FrameImages& held, const FrameImages& drawn) {
    TERRAIN_ASSERT(held.rgba.size() == drawn.rgba.size() &&
                       held.depth.size() == drawn.depth.size() &&
                       held.depth.size() * 4 == held.rgba.size(),
                   "lodSwitchChange: sizes differ");
    double sum = 0.0;
    std::size_t both = 0, jumps = 0;
    for (std::size_t i = 0; i < held.depth.size(); ++i) {
        if (!held.drawn(i) || !drawn.drawn(i)) continue;
        const double change = pixelChange(held.rgba, drawn.rgba, i);
        sum += change;
        jumps += change > LodSwitchChange::kJumpLevels ? 1 : 0;
        ++both;
    }
    if (both == 0) return {.meanLevels = 0.0, .jumpShare = 0.0};
    return {.meanLevels = sum / static_cast<double>(both),
            .jumpShare = static_cast<double>(jumps) / static_cast<double>(both)};
}

double poppingLevels(std::span<const std::uint8_t> lodPrevious, std::span<const std::uint8_t> lod,
                     std::span<const std::uint8_t> referencePrevious,
                     std::span<const std::uint8_t> reference) {
    TERRAIN_ASSERT(lodPrevious.size() == lod.size() && referencePrevious.size() == lod.size() &&
                       reference.size() == lod.size() && lod.size() % 4 == 0,
                   "poppingLevels: sizes differ");
    const std::size_t pixels = lod.size() / 4;
    if (pixels == 0) return 0.0;
    double sum = 0.0;
    for (std::size_t i = 0; i < pixels; ++i) {
        sum += std::max(
            0.0, pixelChange(lodPrevious, lod, i) - pixelChange(referencePrevious, reference, i));
    }
    return sum / static_cast<double>(pixels);
}

}  // namespace terrain::runtime
