#include "terrain/runtime/GlobeScreenSpaceError.h"

#include "ErrorImageSummary.h"
#include "terrain/base/Assert.h"
#include "terrain/globe/Wgs84.h"
#include "terrain/runtime/ScreenProjection.h"

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace terrain::runtime {

ScreenSpaceErrorStats measureGlobeScreenSpaceError(const Camera& camera,
                                                   std::span<const float> lodDepth,
                                                   std::span<const float> lodDepthNoSkirts,
                                                   const GlobeReferenceHeights& referenceHeights,
                                                   double thresholdPx) {
    const int w = camera.viewportWidth, h = camera.viewportHeight;
    const std::size_t pixels = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
    TERRAIN_ASSERT(lodDepth.size() == pixels, "measureGlobeScreenSpaceError: depth size");
    TERRAIN_ASSERT(lodDepthNoSkirts.empty() || lodDepthNoSkirts.size() == pixels);
    const glm::dmat4 viewProjection = camera.relativeViewProjection();
    const glm::dmat4 inverse = glm::inverse(viewProjection);
    ScreenSpaceErrorStats stats;
    std::vector<double> errors;
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
            const bool skirt = !lodDepthNoSkirts.empty() && lodDepthNoSkirts[i] != depth;
            const glm::dvec3 relative = unprojectPixel(inverse, w, h, x, y, depth);
            const glm::dvec3 world = camera.position + relative;
            if (!std::isfinite(world.x) || !std::isfinite(world.y) || !std::isfinite(world.z)) {
                ++stats.nonFinitePixels;
                continue;
            }
            const globe::Geodetic drawn = globe::Wgs84::toGeodetic(world);
            const auto [alongAD, alongBC] = referenceHeights(drawn.latitudeDeg, drawn.longitudeDeg);
            const double nearest =
                std::clamp(drawn.height, std::min(alongAD, alongBC), std::max(alongAD, alongBC));
            const glm::dvec3 normal = globe::Wgs84::normalAt(drawn.latitudeDeg, drawn.longitudeDeg);
            const glm::dvec2 centre = projectToPixels(viewProjection, w, h, relative);
            const auto distancePx = [&](double height) {
                if (height == drawn.height) return 0.0;
                const glm::dvec3 reference =
                    globe::Wgs84::pointAlongNormal(normal, height) - camera.position;
                const glm::dvec2 q = projectToPixels(viewProjection, w, h, reference);
                if (std::isnan(q.x)) return std::numeric_limits<double>::infinity();
                return glm::length(q - centre);
            };
            const double errorPx = distancePx(nearest);
            if (skirt && !std::isnan(centre.x)) {
                countSkirtPixel(stats, errorPx);
                continue;
            }
            if (!std::isfinite(errorPx) || std::isnan(centre.x)) {
                ++stats.nonFinitePixels;
                continue;
            }
            const double fixedPx = distancePx(alongAD);
            ++stats.pixels;
            sum += errorPx;
            errors.push_back(errorPx);
            errorImage[i] = static_cast<float>(errorPx);
            measuredAt[i] = glm::dvec4(world, nearest);
            if (std::isfinite(fixedPx)) {
                sumFixed += fixedPx;
                stats.maxFixedDiagonalPx = std::max(stats.maxFixedDiagonalPx, fixedPx);
            } else {
                ++stats.unboundedComparisonPixels;
            }
            stats.maxSinglePixelPx = std::max(stats.maxSinglePixelPx, errorPx);
            if (errorPx > thresholdPx) {
                ++stats.pixelsOverThreshold;
                if (stats.overThreshold.size() < ScreenSpaceErrorStats::kMaxKeptPixels)
                    stats.overThreshold.push_back(
                        {.x = x, .y = y, .world = world, .surfaceM = nearest, .errorPx = errorPx});
            }
        }
    }
    summariseErrorImage(w, h, errorImage, measuredAt, errors, sum, sumFixed, stats);
    return stats;
}

}  // namespace terrain::runtime
