// ScreenSpaceError: unproject the LOD's depth in double, look up the full-resolution
// surface below, project both points, measure pixels.
#include "terrain/runtime/ScreenSpaceError.h"

#include "ErrorImageSummary.h"

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>

namespace terrain::runtime {

Result<ScreenSpaceErrorStats> measureScreenSpaceError(
    const Camera& camera, std::span<const float> lodDepth, std::span<const float> lodDepthNoSkirts,
    std::span<const float> referenceDepth, FullResolutionSurface& surface, double thresholdPx,
    double horizontalTolerancePx) {
    const int w = camera.viewportWidth, h = camera.viewportHeight;
    const std::size_t pixels = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
    TERRAIN_ASSERT(lodDepth.size() == pixels, "measureScreenSpaceError: depth size");
    TERRAIN_ASSERT(lodDepthNoSkirts.empty() || lodDepthNoSkirts.size() == pixels);
    TERRAIN_ASSERT(referenceDepth.empty() || referenceDepth.size() == pixels);

    const glm::dmat4 viewProjection = camera.relativeViewProjection();
    const glm::dmat4 inverse = glm::inverse(viewProjection);
    ScreenSpaceErrorStats stats;
    std::vector<double> errors;
    // Per pixel: the error, −1 where nothing was measured; and what it was measured
    // against, for the report of the worst pixel.
    std::vector<float> errorImage(pixels, -1.0f);
    std::vector<glm::dvec4> measuredAt(pixels);
    double sum = 0.0, sumFixed = 0.0;
    // The projected distance between W_lod (at the pixel's centre, by construction) and the
    // point at height `z` straight above or below it; +∞ if that point is behind the camera.
    const auto verticalPx = [&](const glm::dvec3& relative, const glm::dvec2& centre, double dz) {
        if (dz == 0.0) return 0.0;
        const glm::dvec2 q = projectToPixels(viewProjection, w, h, relative + glm::dvec3(0, 0, dz));
        if (std::isnan(q.x)) return std::numeric_limits<double>::infinity();
        return glm::length(q - centre);
    };
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
            auto below = surface.heightAt(world.x, world.y);
            if (!below) return below.error();
            if (!below.value().inside) {
                // The rasteriser snaps vertices to sub-pixel positions, so a pixel centre
                // just past the DEM's edge may be covered: measure it at the edge when the
                // edge is less than a pixel away on screen.
                const glm::dvec2 edge = surface.clampToDem(world.x, world.y);
                const glm::dvec3 edgeRelative{edge.x - camera.position.x,
                                              edge.y - camera.position.y, relative.z};
                const glm::dvec2 a = projectToPixels(viewProjection, w, h, relative);
                const glm::dvec2 b = projectToPixels(viewProjection, w, h, edgeRelative);
                if (glm::length(a - b) < 1.0) {
                    below = surface.heightAt(edge.x, edge.y);
                    if (!below) return below.error();
                }
            }
            const SurfaceHeight& s = below.value();
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
            const glm::dvec2 centre = projectToPixels(viewProjection, w, h, relative);
            double nearest = std::clamp(world.z, s.lowM, s.highM);
            const double exactPositionPx = verticalPx(relative, centre, nearest - world.z);
            double errorPx = exactPositionPx;
            if (errorPx > 0.0 && horizontalTolerancePx > 0.0) {
                // The drawn point is where the rasteriser put it, which may be
                // `horizontalTolerancePx` off the exact triangle sideways (vertex snapping,
                // float positions); on a slope S that is S times as far vertically (a cliff
                // of slope 1,000 seen from 1 km: 1/256 px of snapping is 7 m, 4 px). So W_lod
                // is measured against the surface over the square of that half-side around its
                // x, y: the truth's lowest and highest heights within that radius.
                const glm::dvec3 besideRelative = unprojectPixel(inverse, w, h, x + 1, y, depth);
                const double radiusM =
                    horizontalTolerancePx * glm::length(besideRelative - relative);
                auto range = surface.heightRange(world.x, world.y, radiusM);
                if (!range) return range.error();
                const HeightRange& r = range.value();
                const double low = r.inside ? std::min(s.lowM, r.lowM) : s.lowM;
                const double high = r.inside ? std::max(s.highM, r.highM) : s.highM;
                nearest = std::clamp(world.z, low, high);
                errorPx = verticalPx(relative, centre, nearest - world.z);
            }
            if (skirt && !std::isnan(centre.x)) {
                countSkirtPixel(stats, errorPx);
                continue;
            }
            if (!std::isfinite(errorPx) || std::isnan(centre.x)) {
                ++stats.nonFinitePixels;
                continue;
            }
            const double fixedPx = verticalPx(relative, centre, s.referenceM - world.z);
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
