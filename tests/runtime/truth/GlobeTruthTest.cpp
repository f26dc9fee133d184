// The measured screen-space error on the globe (ScreenSpaceError.h over a GlobeTruth), without
// a GPU: on a synthetic depth image of a surface 800 m above the ellipsoid, every pixel's
// error is the projected distance to the truth's height along the ellipsoid normal, as
// GeographicLib's own geocentric conversion places both points; a drawn point between the
// truth's two diagonals is exact (0 px) while the fixed diagonal still sees the distance; and
// a truth that cannot be read fails the measure, naming what failed.
#include "terrain/globe/Wgs84.h"
#include "terrain/runtime/GlobeCamera.h"
#include "terrain/runtime/GlobeTruth.h"
#include "terrain/runtime/ScreenSpaceError.h"

#include <gtest/gtest.h>
#include <GeographicLib/Geocentric.hpp>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include <cmath>
#include <utility>
#include <vector>

namespace terrain::test {
namespace {

constexpr double kDrawnM = 800.0;
constexpr double kTruthM = 750.0;  // 50 m below the drawn surface

/// A 48 × 32 px camera 500 m above the drawn surface at Mount Rainier's latitude, 30° down.
runtime::Camera camera() {
    runtime::Camera c;
    c.viewportWidth = 48;
    c.viewportHeight = 32;
    runtime::placeOnGlobe(c, {{46.85, -121.76, 1300.0}, 40.0, -30.0});
    return c;
}

/// Reversed-Z depth of the ellipsoid raised by kDrawnM (its semi-axes lengthened: not at
/// exactly kDrawnM geodetic height, which is what the measure must find), 0 where a ray
/// misses it.
std::vector<float> raisedEllipsoidDepth(const runtime::Camera& c) {
    const double a = globe::Wgs84::kEquatorialRadius + kDrawnM;
    const double b = globe::Wgs84::kPolarRadius + kDrawnM;
    const glm::dmat4 inverse = glm::inverse(c.relativeViewProjection());
    const int w = c.viewportWidth, h = c.viewportHeight;
    std::vector<float> depth(static_cast<std::size_t>(w * h), 0.0f);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const glm::dvec3 d = glm::normalize(runtime::unprojectPixel(inverse, w, h, x, y, 1e-3));
            const glm::dvec3 scale{1.0 / a, 1.0 / a, 1.0 / b};
            const glm::dvec3 o = c.position * scale, e = d * scale;
            const double qa = glm::dot(e, e), qb = 2.0 * glm::dot(o, e), qc = glm::dot(o, o) - 1.0;
            const double disc = qb * qb - 4.0 * qa * qc;
            if (disc < 0.0) continue;
            const double t = (-qb - std::sqrt(disc)) / (2.0 * qa);
            if (t <= 0.0) continue;
            depth[static_cast<std::size_t>(y * w + x)] =
                static_cast<float>(c.nearPlane / glm::dot(t * d, c.forward()));
        }
    }
    return depth;
}

TEST(GlobeTruth, EveryPixelIsTheProjectedDistanceAlongTheNormalAsGeographicLibPlacesIt) {
    const runtime::Camera c = camera();
    const std::vector<float> depth = raisedEllipsoidDepth(c);
    runtime::GlobeTruth truth([](double, double) -> Result<std::pair<double, double>> {
        return std::pair{kTruthM, kTruthM};
    });
    // Threshold 0: every measured pixel is kept with its error.
    auto measured = runtime::measureScreenSpaceError(c, depth, {}, {}, truth, 0.0);
    ASSERT_TRUE(measured) << measured.error().message;
    const runtime::ScreenSpaceErrorStats& e = measured.value();
    ASSERT_GT(e.pixels, 500u);
    ASSERT_EQ(e.overThreshold.size(), e.pixels);
    EXPECT_EQ(e.nonFinitePixels + e.outsidePixels + e.skirtPixels, 0u);

    const GeographicLib::Geocentric& earth = GeographicLib::Geocentric::WGS84();
    const glm::dmat4 vp = c.relativeViewProjection();
    double worstRelative = 0.0, largest = 0.0;
    for (const runtime::PixelError& p : e.overThreshold) {
        double latitude = 0.0, longitude = 0.0, height = 0.0;
        earth.Reverse(p.world.x, p.world.y, p.world.z, latitude, longitude, height);
        EXPECT_NEAR(height, kDrawnM, 30.0) << "the raised ellipsoid is about kDrawnM up";
        glm::dvec3 truthPoint{0.0};
        earth.Forward(latitude, longitude, kTruthM, truthPoint.x, truthPoint.y, truthPoint.z);
        const glm::dvec2 drawnPx =
            runtime::projectToPixels(vp, c.viewportWidth, c.viewportHeight, p.world - c.position);
        const glm::dvec2 truthPx = runtime::projectToPixels(vp, c.viewportWidth, c.viewportHeight,
                                                            truthPoint - c.position);
        const double expected = glm::length(truthPx - drawnPx);
        worstRelative = std::max(worstRelative, std::abs(p.errorPx - expected) / expected);
        largest = std::max(largest, expected);
        EXPECT_EQ(p.surfaceM, kTruthM);
    }
    EXPECT_LT(worstRelative, 1e-6);
    EXPECT_GT(largest, 1.0) << "50 m seen from a kilometre or so spans pixels";
    EXPECT_EQ(e.maxSinglePixelPx, e.maxExactPositionPx) << "no horizontal tolerance";
    EXPECT_EQ(e.maxFixedDiagonalPx, e.maxSinglePixelPx) << "both diagonals at one height";
}

TEST(GlobeTruth, ADrawnPointBetweenTheTwoDiagonalsIsExact) {
    const runtime::Camera c = camera();
    const std::vector<float> depth = raisedEllipsoidDepth(c);
    // The two triangulations 40 m below and 40 m above the drawn surface, everywhere.
    runtime::GlobeTruth truth([](double, double) -> Result<std::pair<double, double>> {
        return std::pair{kDrawnM - 40.0, kDrawnM + 40.0};
    });
    auto measured = runtime::measureScreenSpaceError(c, depth, {}, {}, truth, 0.5);
    ASSERT_TRUE(measured) << measured.error().message;
    const runtime::ScreenSpaceErrorStats& e = measured.value();
    ASSERT_GT(e.pixels, 500u);
    EXPECT_EQ(e.maxSinglePixelPx, 0.0);
    EXPECT_EQ(e.maxPx, 0.0);
    EXPECT_EQ(e.pixelsOverThreshold, 0u);
    // The fixed (first) diagonal is tens of metres off: pixels on screen.
    EXPECT_GT(e.maxFixedDiagonalPx, 0.5);
    EXPECT_GT(e.meanFixedDiagonalPx, 0.0);
}

TEST(GlobeTruth, ATruthThatCannotBeReadFailsTheMeasure) {
    const runtime::Camera c = camera();
    const std::vector<float> depth = raisedEllipsoidDepth(c);
    int calls = 0;
    runtime::GlobeTruth truth([&calls](double, double) -> Result<std::pair<double, double>> {
        ++calls;
        return Error{"planet.pyramid/shards/3-0-0.shard: truncated"};
    });
    auto measured = runtime::measureScreenSpaceError(c, depth, {}, {}, truth, 1.0);
    ASSERT_FALSE(measured);
    EXPECT_EQ(measured.error().message, "planet.pyramid/shards/3-0-0.shard: truncated");
    EXPECT_EQ(calls, 1) << "the first failure ends the measure";
}

}  // namespace
}  // namespace terrain::test
