// Seams between globe sources (docs/globe.md, "How it works"; SeamBand.h): where a finer
// source ends over a coarser one, the band it is blended across follows the height step, so
// the slope the blend adds stays within the source's own 99th-percentile slope (the issue's
// target) instead of a wall over a fixed 24 pixels; the band is continuous at the corners,
// and only the band is sampled.
#include "terrain/build/GlobeSourceSurface.h"
#include "terrain/build/SeamBand.h"

#include "GeographicFunctionDem.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace terrain::io {
namespace {

constexpr double kMetresPerPixel = 100.0;

// A source of `width` × `height` pixels of 100 m with every edge, whose blend may add `limit`
// at any width, and the step `step` (column, row) under it.
SeamBand::Source squarePixels(
    std::int64_t width, std::int64_t height, double limit,
    std::function<std::optional<double>(std::int64_t, std::int64_t)> step) {
    SeamBand::Source source;
    source.width = width;
    source.height = height;
    source.edges = {true, true, true, true};
    source.slopeLimit = [limit](SeamEdge, double) { return limit; };
    source.eastWestMetres = [](std::int64_t) { return kMetresPerPixel; };
    source.northSouthMetres = [](std::int64_t) { return kMetresPerPixel; };
    source.step = std::move(step);
    return source;
}

// The width one step needs where the width changes along the edge (SeamBand::fit): 1.5 ·
// |step| / (pixel metres · limit), widened by √(1 + k²) on square pixels.
double neededPixels(double step, double limit) {
    return 1.5 * std::hypot(1.0, SeamBand::kWidthChangePerPixel) * step / (kMetresPerPixel * limit);
}

TEST(SeamBand, WidthFollowsTheStep) {
    // 1 km above the source beneath along rows 100–150 of the west edge, 50 m everywhere else.
    std::int64_t sampled = 0;
    const auto step = [&](std::int64_t column, std::int64_t row) -> std::optional<double> {
        ++sampled;
        return column < 200 && row >= 100 && row <= 150 ? 1000.0 : 50.0;
    };
    const SeamBand band = SeamBand::fit(squarePixels(400, 1000, 0.2, step));
    // The small step keeps the narrowest band: on the other edges, and far along this one.
    EXPECT_EQ(band.widthAt(SeamEdge::East, 125.0), SeamBand::kMinimumPixels);
    EXPECT_EQ(band.widthAt(SeamEdge::North, 10.0), SeamBand::kMinimumPixels);
    EXPECT_EQ(band.widthAt(SeamEdge::West, 900.0), SeamBand::kMinimumPixels);
    // The big one widens it as much as its slope needs (77 px), no more.
    const double needed = neededPixels(1000.0, 0.2);
    EXPECT_GT(needed, 3.0 * SeamBand::kMinimumPixels);
    EXPECT_NEAR(band.widthAt(SeamEdge::West, 125.0), needed, 0.01);
    EXPECT_NEAR(band.widestPixels(), needed, 0.01);
    EXPECT_EQ(band.narrowestPixels(), SeamBand::kMinimumPixels);
    EXPECT_EQ(band.cappedPixels(), 0);
    // The width changes slowly along the edge, falling to the narrowest on either side.
    for (std::int64_t t = 1; t < band.along(SeamEdge::West); ++t)
        EXPECT_LE(std::abs(band.widthAt(SeamEdge::West, double(t)) -
                           band.widthAt(SeamEdge::West, double(t - 1))),
                  SeamBand::kWidthChangePerPixel + 1e-4)
            << "row " << t;
    EXPECT_NEAR(band.widthAt(SeamEdge::West, 50.0), needed - 50.0 * SeamBand::kWidthChangePerPixel,
                0.01);
    // Only the band was sampled: its pixels along each edge, not the source's 400 000.
    EXPECT_LT(sampled, 2 * (400 + 1000) * 30 + 300 * 80);

    // A step too big for a quarter of the source: the band stops there and says so.
    const auto cliff = [](std::int64_t column, std::int64_t row) -> std::optional<double> {
        return column < 200 && row >= 100 && row <= 150 ? 3000.0 : 50.0;
    };
    const SeamBand capped = SeamBand::fit(squarePixels(400, 1000, 0.2, cliff));
    EXPECT_GT(neededPixels(3000.0, 0.2), 100.0);
    EXPECT_EQ(capped.widthAt(SeamEdge::West, 125.0), 100.0);  // a quarter of 400 pixels
    EXPECT_EQ(capped.cappedPixels(), 51);
}

TEST(SeamBand, LimitThatFallsWithTheWidthIsMetAtTheWidthFound) {
    // A source whose steep slopes are short: the limit over a baseline halves from 24 to 96 px.
    SeamBand::Source source =
        squarePixels(600, 600, 0.0, [](std::int64_t, std::int64_t) { return 800.0; });
    const auto limit = [](double widthPx) { return 0.3 * std::pow(24.0 / widthPx, 0.5); };
    source.slopeLimit = [&](SeamEdge, double widthPx) { return limit(widthPx); };
    const SeamBand band = SeamBand::fit(source);
    const double w = band.widthAt(SeamEdge::South, 300.0);
    EXPECT_GT(w, neededPixels(800.0, limit(SeamBand::kMinimumPixels)));
    // Within a pixel of the fixed point: wide enough for the limit at its own width.
    EXPECT_GE(w + 1.0, neededPixels(800.0, limit(w)));
    EXPECT_LE(w, neededPixels(800.0, limit(w)) + 1.0);
}

TEST(SeamBand, WeightIsContinuousAtTheCorners) {
    // A wide band on the west edge (a big step by its north end), the narrowest elsewhere.
    const auto step = [](std::int64_t column, std::int64_t row) -> std::optional<double> {
        return column < 100 && row >= 40 && row < 150 ? 1500.0 : 100.0;
    };
    const SeamBand band = SeamBand::fit(squarePixels(400, 300, 0.3, step));
    ASSERT_GT(band.widthAt(SeamEdge::West, 0.0), 2.0 * band.widthAt(SeamEdge::North, 0.0));
    // 0 on every edge, 1 beyond every band, and nowhere steeper than smoothstep's 1.5 / W
    // (widened by the width's change along the edge) over the narrowest W: no step at a
    // corner, where the two bands meet.
    const double lipschitz =
        1.5 * std::hypot(1.0, SeamBand::kWidthChangePerPixel) / SeamBand::kMinimumPixels;
    constexpr double kStep = 0.25;
    for (const auto& [x0, y0] : {std::pair{0.0, 0.0}, std::pair{400.0, 0.0}, std::pair{0.0, 300.0},
                                 std::pair{400.0, 300.0}}) {
        const double sx = x0 == 0.0 ? 1.0 : -1.0, sy = y0 == 0.0 ? 1.0 : -1.0;
        for (double i = 0.0; i <= 140.0; i += kStep) {
            EXPECT_EQ(band.weight(x0 + sx * i, y0), 0.0);
            EXPECT_EQ(band.weight(x0, y0 + sy * i), 0.0);
            for (double j = 0.0; j <= 140.0; j += kStep) {
                const double x = x0 + sx * i, y = y0 + sy * j;
                const double w = band.weight(x, y);
                EXPECT_LE(std::abs(band.weight(x + sx * kStep, y) - w), lipschitz * kStep + 1e-9)
                    << x << ", " << y;
                EXPECT_LE(std::abs(band.weight(x, y + sy * kStep) - w), lipschitz * kStep + 1e-9)
                    << x << ", " << y;
            }
        }
    }
    EXPECT_EQ(band.weight(200.0, 150.0), 1.0);
}

// A 1° tile of 0.0025° (278 m north–south, 195 m east–west at 45.5° N) over a 0 m grid of
// 2°: a crater whose rim, the tile's edge, stands 3 km above the grid and falls inwards at
// 0.25 (its 99th-percentile slope, at every baseline up to the wall's 12 km) to the grid's
// level. Blended over 24 pixels (4.7 km east–west) the 2.4 km step in their middle would make
// a 0.77 slope, three times the tile's steepest; over some 60 pixels, no steeper than the
// tile's own.
constexpr double kRimM = 3000.0, kWallSlope = 0.25;

float crater(double latitude, double longitude) {
    const double eastWest = 111320.0 * std::cos(latitude * std::numbers::pi / 180.0);
    const double northSouth = 111132.0;
    const double inside =
        std::min({(longitude - 10.0) * eastWest, (11.0 - longitude) * eastWest,
                  (latitude - 45.0) * northSouth, (46.0 - latitude) * northSouth});
    return static_cast<float>(std::max(0.0, kRimM - kWallSlope * inside));
}

TEST(GlobeSeams, SlopeTheBlendAddsStaysWithinTheSources) {
    test::GeographicFunctionDem coarse(-180.0, 90.0, 180, 90, 2.0, 2.0,
                                       [](double, double) { return 0.0f; });
    test::GeographicFunctionDem fine(10.0, 46.0, 400, 400, 0.0025, 0.0025, crater);
    DemReader* const sources[] = {&fine, &coarse};
    auto surface = GlobeSourceSurface::read(sources, std::uint64_t{1} << 30, 16);
    ASSERT_TRUE(surface) << surface.error().message;
    const std::vector<ManifestSeam> seams = surface.value().seams();
    ASSERT_EQ(seams.size(), 1u);  // the coarse grid lies over nothing
    const ManifestSeam& seam = seams[0];
    ::testing::Test::RecordProperty("seamSlope", std::to_string(seam.seamSlope));
    ::testing::Test::RecordProperty("sourceSlopeP99", std::to_string(seam.sourceSlopeP99));
    ::testing::Test::RecordProperty("bandPixels", std::to_string(seam.bandPixels[1]));
    EXPECT_EQ(seam.input, "geographic-function-dem");
    EXPECT_NEAR(seam.largestStepM, kRimM, 30.0);
    EXPECT_NEAR(seam.sourceSlopeP99, kWallSlope, 0.01);
    // What 24 pixels would add to the 2.4 km step in their middle: three times the tile's.
    const double fixedBand =
        1.5 * (kRimM - kWallSlope * 12.0 * 195.0) / (SeamBand::kMinimumPixels * 195.0);
    EXPECT_GT(fixedBand, 3.0 * seam.sourceSlopeP99);
    // The band follows the step instead: the target, and the slopes over its width.
    EXPECT_LE(seam.seamSlope, seam.sourceSlopeP99);
    EXPECT_LE(seam.bandScaleRatio, 1.02);  // the weight's slope by finite differences
    EXPECT_GT(seam.bandPixels[1], 2.0 * SeamBand::kMinimumPixels);
    EXPECT_GE(seam.bandPixels[0], SeamBand::kMinimumPixels);
    EXPECT_EQ(seam.cappedPixels, 0);

    // The composite meets the coarse grid at the tile's edge and rises from it without a wall,
    // along the edges and across the north-east corner: no two places 1/8 pixel apart differ by
    // more than the tile's steepest slope and the seam's together allow.
    const auto height = [&](double latitude, double longitude) {
        return surface.value().heightsAt(latitude, longitude).first;
    };
    // (On the composite's mesh: the edge pixel's centre, weighted 3 (0.5 / W)², holds a metre
    // or so of the 3 km.)
    EXPECT_NEAR(height(46.0, 11.0), 0.0, 2.0);
    EXPECT_NEAR(height(45.5, 10.0), 0.0, 2.0);
    const double steepest = kWallSlope * std::sqrt(2.0);  // the mesh's, across a corner

    const double eighth = 0.0025 / 8.0;
    for (double i = 0.0; i < 200.0; i += 1.0) {
        for (double j = 0.0; j < 200.0; j += 7.0) {
            const double latitude = 46.0 - j * eighth, longitude = 11.0 - i * eighth;
            const double here = height(latitude, longitude);
            const double eastWest =
                eighth * 111320.0 * std::cos(latitude * std::numbers::pi / 180.0);
            const double northSouth = eighth * 111132.0;
            EXPECT_LE(std::abs(height(latitude, longitude - eighth) - here),
                      (steepest + seam.seamSlope) * eastWest)
                << latitude << ", " << longitude;
            EXPECT_LE(std::abs(height(latitude - eighth, longitude) - here),
                      (steepest + seam.seamSlope) * northSouth)
                << latitude << ", " << longitude;
        }
    }
}

}  // namespace
}  // namespace terrain::io
