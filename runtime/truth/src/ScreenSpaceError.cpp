// ScreenSpaceError: unproject the LOD's depth in double, find the truth on the vertical
// through it, project both points, measure pixels; then what the image of per-pixel errors
// says (the largest error two adjacent pixels both show, the mean, the 99th percentile).
#include "terrain/runtime/ScreenSpaceError.h"

#include "terrain/base/Assert.h"

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace terrain::runtime {
namespace {

/// Counts a skirt pixel of error `errorPx` (+∞ when its segment to the truth passes behind
/// the camera).
void countSkirtPixel(ScreenSpaceErrorStats& stats, double errorPx) {
    ++stats.skirtPixels;
    if (std::isfinite(errorPx)) {
        stats.skirtMaxPx = std::max(stats.skirtMaxPx, errorPx);
    } else {
        ++stats.skirtUnboundedPixels;
    }
}

/// `errorImage`: per pixel (rows bottom-up) the error, −1 where nothing was measured;
/// `measuredAt`: per pixel W_lod (xyz) and the truth's height it was measured against (w);
/// `errors`: the measured errors (reordered); `sum`, `sumFixed`: their sums (primary, fixed
/// diagonal). Fills maxPx, worst*, meanPx, meanFixedDiagonalPx and p99Px of `stats`, whose
/// `pixels` must already be counted.
void summariseErrorImage(int w, int h, std::span<const float> errorImage,
                         std::span<const glm::dvec4> measuredAt, std::vector<double>& errors,
                         double sum, double sumFixed, ScreenSpaceErrorStats& stats) {
    // The largest error two adjacent pixels both show: for every pixel, the smaller of its
    // own error and its largest measured 8-neighbour's.
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(w) +
                                  static_cast<std::size_t>(x);
            if (errorImage[i] < 0.0f) continue;
            float neighbour = -1.0f;
            for (int j = std::max(y - 1, 0); j <= std::min(y + 1, h - 1); ++j) {
                for (int k = std::max(x - 1, 0); k <= std::min(x + 1, w - 1); ++k) {
                    if (j == y && k == x) continue;
                    neighbour = std::max(
                        neighbour,
                        errorImage[static_cast<std::size_t>(j) * static_cast<std::size_t>(w) +
                                   static_cast<std::size_t>(k)]);
                }
            }
            if (neighbour < 0.0f) continue;  // a lone measured pixel shows nothing twice
            const double shared =
                std::min(static_cast<double>(errorImage[i]), static_cast<double>(neighbour));
            if (shared > stats.maxPx || stats.worstX < 0) {
                stats.maxPx = shared;
                stats.worstX = x;
                stats.worstY = y;
                stats.worstWorld = glm::dvec3(measuredAt[i]);
                stats.worstReferenceM = measuredAt[i].w;
            }
        }
    }
    if (stats.pixels > 0) {
        const auto n = static_cast<double>(stats.pixels);
        stats.meanPx = sum / n;
        const auto bounded = static_cast<double>(stats.pixels - stats.unboundedComparisonPixels);
        stats.meanFixedDiagonalPx = bounded > 0.0 ? sumFixed / bounded : 0.0;
        const auto rank = static_cast<std::size_t>(std::ceil(0.99 * n)) - 1;
        std::nth_element(errors.begin(), errors.begin() + static_cast<std::ptrdiff_t>(rank),
                         errors.end());
        stats.p99Px = errors[rank];
    }
}

}  // namespace

Result<ScreenSpaceErrorStats> measureScreenSpaceError(const Camera& camera,
                                                      std::span<const float> lodDepth,
                                                      std::span<const float> lodDepthNoSkirts,
                                                      std::span<const float> referenceDepth,
                                                      TruthSurface& truth, double thresholdPx) {
    const int w = camera.viewportWidth, h = camera.viewportHeight;
    const std::size_t pixels = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
    TERRAIN_ASSERT(lodDepth.size() == pixels, "measureScreenSpaceError: depth size");
    TERRAIN_ASSERT(lodDepthNoSkirts.empty() || lodDepthNoSkirts.size() == pixels);
    TERRAIN_ASSERT(referenceDepth.empty() || referenceDepth.size() == pixels);

    const FrameProjection frame{.cameraPosition = camera.position,
                                .viewProjection = camera.relativeViewProjection(),
                                .widthPx = w,
                                .heightPx = h};
    const glm::dmat4 inverse = glm::inverse(frame.viewProjection);
    const double horizontalTolerancePx = truth.horizontalTolerancePx();
    ScreenSpaceErrorStats stats;
    std::vector<double> errors;
    // Per pixel: the error, −1 where nothing was measured; and what it was measured
    // against, for the report of the worst pixel.
    std::vector<float> errorImage(pixels, -1.0f);
    std::vector<glm::dvec4> measuredAt(pixels);
    double sum = 0.0, sumFixed = 0.0;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(w) +
                                  static_cast<std::size_t>(x);
            const float depth = lodDepth[i];
            if (std::isnan(depth)) {
                ++stats.nonFinitePixels;
                continue;
            }
            if (!(depth > 0.0f)) continue;  // nothing drawn
            if (!referenceDepth.empty() && !(referenceDepth[i] > 0.0f)) continue;
            const bool skirt = !lodDepthNoSkirts.empty() && lodDepthNoSkirts[i] != depth;
            const glm::dvec3 relative = unprojectPixel(inverse, w, h, x, y, depth);
            const glm::dvec3 world = camera.position + relative;
            if (!std::isfinite(world.x) || !std::isfinite(world.y) || !std::isfinite(world.z)) {
                ++stats.nonFinitePixels;
                continue;
            }
            auto vertical = truth.verticalAt(world, relative, frame);
            if (!vertical) return vertical.error();
            const TruthVertical& s = vertical.value();
            if (!s.inside) {
                if (skirt) {
                    ++stats.skirtPixels;
                } else {
                    ++stats.outsidePixels;
                }
                continue;
            }
            // The projection of W_lod: the pixel's centre, up to rounding; projecting it too
            // keeps both ends of the segment under the same arithmetic.
            const glm::dvec2 centre = frame.toPixels(relative);
            // The projected distance from W_lod to the point of `v` at `heightM`; +∞ if that
            // point is behind the camera.
            const auto verticalPx = [&](const TruthVertical& v, double heightM) {
                if (heightM == v.drawnM) return 0.0;
                const glm::dvec2 q =
                    frame.toPixels(truth.relativePointAt(v, relative, frame, heightM));
                if (std::isnan(q.x)) return std::numeric_limits<double>::infinity();
                return glm::length(q - centre);
            };
            double nearest = std::clamp(s.drawnM, s.lowM, s.highM);
            const double exactPositionPx = verticalPx(s, nearest);
            double errorPx = exactPositionPx;
            if (errorPx > 0.0 && horizontalTolerancePx > 0.0) {
                // The drawn point may lie that far off the exact triangle sideways: it is
                // measured against the truth over the square of that half-side around it.
                const glm::dvec3 besideRelative = unprojectPixel(inverse, w, h, x + 1, y, depth);
                const double radiusM =
                    horizontalTolerancePx * glm::length(besideRelative - relative);
                auto wide = truth.widened(s, world, radiusM);
                if (!wide) return wide.error();
                nearest = std::clamp(s.drawnM, wide.value().lowM, wide.value().highM);
                errorPx = verticalPx(s, nearest);
            }
            if (skirt && !std::isnan(centre.x)) {
                countSkirtPixel(stats, errorPx);
                continue;
            }
            if (!std::isfinite(errorPx) || std::isnan(centre.x)) {
                ++stats.nonFinitePixels;
                continue;
            }
            const double fixedPx = verticalPx(s, s.referenceM);
            ++stats.pixels;
            sum += errorPx;
            errors.push_back(errorPx);
            errorImage[i] = static_cast<float>(errorPx);
            measuredAt[i] = glm::dvec4(world, nearest);
            stats.maxSinglePixelPx = std::max(stats.maxSinglePixelPx, errorPx);
            if (std::isfinite(fixedPx) && std::isfinite(exactPositionPx)) {
                sumFixed += fixedPx;
                stats.maxFixedDiagonalPx = std::max(stats.maxFixedDiagonalPx, fixedPx);
                stats.maxExactPositionPx = std::max(stats.maxExactPositionPx, exactPositionPx);
            } else {
                ++stats.unboundedComparisonPixels;
            }
            if (errorPx > thresholdPx) {
                ++stats.pixelsOverThreshold;
                if (stats.overThreshold.size() < ScreenSpaceErrorStats::kMaxKeptPixels) {
                    stats.overThreshold.push_back(
                        {.x = x, .y = y, .world = world, .surfaceM = nearest, .errorPx = errorPx});
                }
            }
        }
    }
    summariseErrorImage(w, h, errorImage, measuredAt, errors, sum, sumFixed, stats);
    return stats;
}

}  // namespace terrain::runtime
