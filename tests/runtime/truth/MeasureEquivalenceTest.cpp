// Temporary (issue 45): the one measure of ScreenSpaceError.h over a TruthSurface against
// copies of the two loops it replaces (the plane's over FullResolutionSurface, the globe's
// over a function of latitude and longitude), field for field, bit for bit, on synthetic
// depth images: the plane with tolerance 0 and 0.05 px and the DEM's edge in view, the globe
// from orbit to below the ground. A later commit replaces it with GlobeTruthTest.
#include "GlobeTestSources.h"
#include "TempFolder.h"
#include "TinyPyramid.h"
#include "terrain/globe/Wgs84.h"
#include "terrain/runtime/FullResolutionSurface.h"
#include "terrain/runtime/GlobeCamera.h"
#include "terrain/runtime/GlobeTruth.h"
#include "terrain/runtime/PlaneTruth.h"
#include "terrain/runtime/ScreenSpaceError.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>

namespace terrain::test {
namespace {

using runtime::ScreenSpaceErrorStats;

// ---- The old loops, as they were (ErrorImageSummary.cpp, ScreenSpaceError.cpp,
// GlobeScreenSpaceError.cpp at 8ff9c7a). ----

void oldSummarise(int w, int h, std::span<const float> errorImage,
                  std::span<const glm::dvec4> measuredAt, std::vector<double>& errors, double sum,
                  double sumFixed, ScreenSpaceErrorStats& stats) {
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
            if (neighbour < 0.0f) continue;
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

void oldCountSkirtPixel(ScreenSpaceErrorStats& stats, double errorPx) {
    ++stats.skirtPixels;
    if (std::isfinite(errorPx)) {
        stats.skirtMaxPx = std::max(stats.skirtMaxPx, errorPx);
    } else {
        ++stats.skirtUnboundedPixels;
    }
}

Result<ScreenSpaceErrorStats> oldPlaneMeasure(const runtime::Camera& camera,
                                              std::span<const float> lodDepth,
                                              std::span<const float> lodDepthNoSkirts,
                                              std::span<const float> referenceDepth,
                                              runtime::FullResolutionSurface& surface,
                                              double thresholdPx, double horizontalTolerancePx) {
    using namespace runtime;
    const int w = camera.viewportWidth, h = camera.viewportHeight;
    const std::size_t pixels = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
    const glm::dmat4 viewProjection = camera.relativeViewProjection();
    const glm::dmat4 inverse = glm::inverse(viewProjection);
    ScreenSpaceErrorStats stats;
    std::vector<double> errors;
    std::vector<float> errorImage(pixels, -1.0f);
    std::vector<glm::dvec4> measuredAt(pixels);
    double sum = 0.0, sumFixed = 0.0;
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
            if (!(depth > 0.0f)) continue;
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
            const glm::dvec2 centre = projectToPixels(viewProjection, w, h, relative);
            double nearest = std::clamp(world.z, s.lowM, s.highM);
            const double exactPositionPx = verticalPx(relative, centre, nearest - world.z);
            double errorPx = exactPositionPx;
            if (errorPx > 0.0 && horizontalTolerancePx > 0.0) {
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
                oldCountSkirtPixel(stats, errorPx);
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
    oldSummarise(w, h, errorImage, measuredAt, errors, sum, sumFixed, stats);
    return stats;
}

using OldGlobeHeights = std::function<std::pair<double, double>(double, double)>;

ScreenSpaceErrorStats oldGlobeMeasure(const runtime::Camera& camera,
                                      std::span<const float> lodDepth,
                                      std::span<const float> lodDepthNoSkirts,
                                      const OldGlobeHeights& referenceHeights, double thresholdPx) {
    using namespace runtime;
    const int w = camera.viewportWidth, h = camera.viewportHeight;
    const std::size_t pixels = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
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
            if (!(depth > 0.0f)) continue;
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
                oldCountSkirtPixel(stats, errorPx);
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
    oldSummarise(w, h, errorImage, measuredAt, errors, sum, sumFixed, stats);
    return stats;
}

// ---- The comparison. ----

bool same(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool same(const glm::dvec3& a, const glm::dvec3& b) {
    return same(a.x, b.x) && same(a.y, b.y) && same(a.z, b.z);
}

/// Every field bit for bit; `exactPositionTooOld`: the old globe loop left
/// maxExactPositionPx at 0 (it had no horizontal tolerance to be without), the one measure
/// fills it, so it is compared with what it must be instead.
void expectSame(const ScreenSpaceErrorStats& a, const ScreenSpaceErrorStats& b,
                bool exactPositionTooOld = true) {
    EXPECT_EQ(a.pixels, b.pixels);
    EXPECT_TRUE(same(a.maxPx, b.maxPx)) << a.maxPx << " vs " << b.maxPx;
    EXPECT_TRUE(same(a.maxSinglePixelPx, b.maxSinglePixelPx));
    if (exactPositionTooOld) {
        EXPECT_TRUE(same(a.maxExactPositionPx, b.maxExactPositionPx));
    }
    EXPECT_TRUE(same(a.meanPx, b.meanPx));
    EXPECT_TRUE(same(a.p99Px, b.p99Px));
    EXPECT_EQ(a.pixelsOverThreshold, b.pixelsOverThreshold);
    ASSERT_EQ(a.overThreshold.size(), b.overThreshold.size());
    for (std::size_t i = 0; i < a.overThreshold.size(); ++i) {
        const runtime::PixelError &p = a.overThreshold[i], &q = b.overThreshold[i];
        EXPECT_TRUE(p.x == q.x && p.y == q.y && same(p.world, q.world) &&
                    same(p.surfaceM, q.surfaceM) && same(p.errorPx, q.errorPx))
            << "over-threshold pixel " << i;
    }
    EXPECT_TRUE(same(a.maxFixedDiagonalPx, b.maxFixedDiagonalPx));
    EXPECT_TRUE(same(a.meanFixedDiagonalPx, b.meanFixedDiagonalPx));
    EXPECT_EQ(a.skirtPixels, b.skirtPixels);
    EXPECT_TRUE(same(a.skirtMaxPx, b.skirtMaxPx));
    EXPECT_EQ(a.skirtUnboundedPixels, b.skirtUnboundedPixels);
    EXPECT_EQ(a.outsidePixels, b.outsidePixels);
    EXPECT_EQ(a.nonFinitePixels, b.nonFinitePixels);
    EXPECT_EQ(a.unboundedComparisonPixels, b.unboundedComparisonPixels);
    EXPECT_EQ(a.worstX, b.worstX);
    EXPECT_EQ(a.worstY, b.worstY);
    EXPECT_TRUE(same(a.worstWorld, b.worstWorld));
    EXPECT_TRUE(same(a.worstReferenceM, b.worstReferenceM));
}

/// A deterministic factor near 1 per pixel, so that the drawn surface is off the truth by
/// a few pixels here and there.
float jitter(std::size_t i) {
    const std::uint32_t hash = static_cast<std::uint32_t>(i) * 2654435761u;
    return 1.0f + 0.02f * (static_cast<float>(hash >> 16) / 65535.0f - 0.5f);
}

/// Skirt pixels (a skirtless depth that differs), NaN and undrawn pixels, and where the
/// reference drew nothing, sprinkled over `depth`.
void sprinkle(std::vector<float>& depth, std::vector<float>& noSkirts,
              std::vector<float>& reference) {
    noSkirts = depth;
    reference = depth;
    for (std::size_t i = 0; i < depth.size(); ++i) {
        depth[i] *= jitter(i);
        noSkirts[i] = depth[i];
        if (i % 7 == 3) noSkirts[i] = 0.0f;
        if (i % 31 == 5) depth[i] = std::numeric_limits<float>::quiet_NaN();
        if (i % 37 == 11) reference[i] = 0.0f;
    }
}

TEST(MeasureEquivalence, ThePlaneMeasuresAsItsOldLoop) {
    TempFolder folder;
    TinyPyramidOptions options;
    options.width = 37;
    options.height = 29;
    const auto path = folder.path() / "tiny.pyramid";
    auto written = writeTinyPyramid(path, options);
    ASSERT_TRUE(written) << written.error().message;
    auto opened = runtime::FullResolutionSurface::open(path);
    ASSERT_TRUE(opened) << opened.error().message;
    runtime::FullResolutionSurface& s = opened.value();
    const runtime::TerrainGeometry& g = s.geometry();
    // Two views over a plane at 100 m through the DEM's relief (±130 m): the whole DEM with
    // its edges and beyond, and close over its south-east corner.
    runtime::Camera far;
    far.viewportWidth = 64;
    far.viewportHeight = 48;
    far.fovY = 1.2;
    far.position = {g.worldAtFraction(0.5, 1.6), 260.0};
    far.lookAt({g.worldAtFraction(0.5, 0.5), 0.0});
    runtime::Camera corner = far;
    corner.position = {g.worldAtFraction(1.1, 1.1), 150.0};
    corner.lookAt({g.worldAtFraction(0.9, 0.9), 60.0});
    for (const runtime::Camera& c : {far, corner}) {
        const glm::dmat4 inverse = glm::inverse(c.relativeViewProjection());
        const int w = c.viewportWidth, h = c.viewportHeight;
        std::vector<float> depth(static_cast<std::size_t>(w * h), 0.0f);
        for (int y = 0; y < h; ++y) {
            for (int x = 0; x < w; ++x) {
                const glm::dvec3 dir =
                    glm::normalize(runtime::unprojectPixel(inverse, w, h, x, y, 1e-3));
                if (dir.z >= 0.0) continue;
                const glm::dvec3 rel = (100.0 - c.position.z) / dir.z * dir;
                depth[static_cast<std::size_t>(y * w + x)] =
                    static_cast<float>(c.nearPlane / glm::dot(rel, c.forward()));
            }
        }
        std::vector<float> noSkirts, reference;
        sprinkle(depth, noSkirts, reference);
        for (const double tolerancePx : {0.0, runtime::kHorizontalTolerancePx}) {
            for (const bool withReference : {false, true}) {
                SCOPED_TRACE("tolerance " + std::to_string(tolerancePx) + ", reference " +
                             std::to_string(withReference));
                const std::span<const float> ref =
                    withReference ? std::span<const float>(reference) : std::span<const float>();
                auto old = oldPlaneMeasure(c, depth, noSkirts, ref, s, 2.0, tolerancePx);
                ASSERT_TRUE(old) << old.error().message;
                runtime::PlaneTruth truth(s, tolerancePx);
                auto now = runtime::measureScreenSpaceError(c, depth, noSkirts, ref, truth, 2.0);
                ASSERT_TRUE(now) << now.error().message;
                EXPECT_GT(old.value().pixels, 40u);
                EXPECT_GT(old.value().outsidePixels, 0u) << "the DEM's edge is in view";
                EXPECT_GT(old.value().skirtPixels, 0u);
                EXPECT_GT(old.value().pixelsOverThreshold, 0u);
                expectSame(now.value(), old.value());
            }
        }
    }
}

TEST(MeasureEquivalence, TheGlobeMeasuresAsItsOldLoop) {
    // Heights of a smooth planet on the two diagonals, tens of metres apart.
    const OldGlobeHeights heights = [](double latitude, double longitude) {
        const double h = hills(latitude, longitude);
        return std::pair{h, h + 40.0 * std::sin(latitude * 3.0 + longitude * 11.0)};
    };
    const runtime::GlobeReferenceHeights truthHeights =
        [&](double latitude, double longitude) -> Result<std::pair<double, double>> {
        return heights(latitude, longitude);
    };
    // From orbit, from an airliner, from a hill top, level from 10 m and from below the
    // ground (where the drawn surface is above the camera).
    struct View {
        double heightM, pitchDeg;
    };
    for (const View v : {View{2.0e7, -90.0}, View{1.0e4, -30.0}, View{2000.0, -10.0},
                         View{10.0, 0.0}, View{-300.0, 20.0}}) {
        SCOPED_TRACE("height " + std::to_string(v.heightM));
        runtime::Camera c;
        c.viewportWidth = 64;
        c.viewportHeight = 48;
        runtime::placeOnGlobe(c, {{46.8, -121.7, v.heightM}, 30.0, v.pitchDeg});
        // The ray through every pixel meets an ellipsoid 800 m above WGS84's.
        const double a = globe::Wgs84::kEquatorialRadius + 800.0,
                     b = globe::Wgs84::kPolarRadius + 800.0;
        const glm::dmat4 inverse = glm::inverse(c.relativeViewProjection());
        const int w = c.viewportWidth, h = c.viewportHeight;
        std::vector<float> depth(static_cast<std::size_t>(w * h), 0.0f);
        for (int y = 0; y < h; ++y) {
            for (int x = 0; x < w; ++x) {
                const glm::dvec3 d =
                    glm::normalize(runtime::unprojectPixel(inverse, w, h, x, y, 1e-3));
                const glm::dvec3 scale{1.0 / a, 1.0 / a, 1.0 / b};
                const glm::dvec3 o = c.position * scale, e = d * scale;
                const double qa = glm::dot(e, e), qb = 2.0 * glm::dot(o, e),
                             qc = glm::dot(o, o) - 1.0;
                const double disc = qb * qb - 4.0 * qa * qc;
                if (disc < 0.0) continue;
                const double root = std::sqrt(disc);
                double t = (-qb - root) / (2.0 * qa);
                if (t <= 0.0) t = (-qb + root) / (2.0 * qa);
                if (t <= 0.0) continue;
                depth[static_cast<std::size_t>(y * w + x)] =
                    static_cast<float>(c.nearPlane / glm::dot(t * d, c.forward()));
            }
        }
        std::vector<float> noSkirts, unused;
        sprinkle(depth, noSkirts, unused);
        const ScreenSpaceErrorStats old = oldGlobeMeasure(c, depth, noSkirts, heights, 2.0);
        runtime::GlobeTruth truth(truthHeights);
        auto now = runtime::measureScreenSpaceError(c, depth, noSkirts, {}, truth, 2.0);
        ASSERT_TRUE(now) << now.error().message;
        EXPECT_GT(old.pixels, 300u);
        EXPECT_GT(old.skirtPixels, 0u);
        expectSame(now.value(), old, false);
        EXPECT_EQ(old.maxExactPositionPx, 0.0);
        EXPECT_LE(now.value().maxExactPositionPx, now.value().maxSinglePixelPx);
        EXPECT_TRUE(old.unboundedComparisonPixels > 0 ||
                    same(now.value().maxExactPositionPx, old.maxSinglePixelPx))
            << "without a horizontal tolerance the exact position's error is the error";
    }
}

}  // namespace
}  // namespace terrain::test
