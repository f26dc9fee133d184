// The no-data fill (docs/pyramid-format.md, "No-data"): each void over the surface beneath it
// (the delta-surface fill), or by the membrane from its whole rim where nothing lies beneath,
// never along the row; rounded to the source's units when the source stores whole numbers, so
// a tile with a filled void keeps one height unit (HeightCodes.h).
#include "terrain/build/NoDataFill.h"
#include "terrain/pyramid/HeightCodes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <vector>

using namespace terrain::io;

namespace {
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

struct Raster {
    std::int64_t width = 0, height = 0;
    std::vector<float> truth;    // the surface before the voids were punched
    std::vector<float> heights;  // with them
    float& at(std::int64_t x, std::int64_t y) {
        return heights[static_cast<std::size_t>(y * width + x)];
    }
};

Raster sampled(std::int64_t width, std::int64_t height,
               const std::function<double(double x, double y)>& surface) {
    Raster r{width, height, {}, {}};
    for (std::int64_t y = 0; y < height; ++y)
        for (std::int64_t x = 0; x < width; ++x)
            r.truth.push_back(static_cast<float>(surface(double(x), double(y))));
    r.heights = r.truth;
    return r;
}

void punch(Raster& r, std::int64_t x0, std::int64_t y0, std::int64_t x1, std::int64_t y1) {
    for (std::int64_t y = y0; y < y1; ++y)
        for (std::int64_t x = x0; x < x1; ++x) r.at(x, y) = kNaN;
}

// The largest |fill − truth| over the punched samples.
double largestError(const Raster& r, const std::vector<std::uint8_t>& valid) {
    double largest = 0.0;
    for (std::size_t i = 0; i < r.heights.size(); ++i)
        if (!valid[i]) largest = std::max(largest, std::abs(double(r.heights[i] - r.truth[i])));
    return largest;
}

// The fill before the membrane: linear along the row between the nearest valid samples, the
// one valid sample's value where the row has valid samples on one side only.
double largestRowLinearError(const Raster& punched) {
    double largest = 0.0;
    for (std::int64_t y = 0; y < punched.height; ++y) {
        const float* row = punched.heights.data() + y * punched.width;
        for (std::int64_t x = 0; x < punched.width; ++x) {
            if (!std::isnan(row[x])) continue;
            std::int64_t w = x, e = x;
            while (w >= 0 && std::isnan(row[w])) --w;
            while (e < punched.width && std::isnan(row[e])) ++e;
            double h = 0.0;
            if (w >= 0 && e < punched.width)
                h = row[w] + (row[e] - row[w]) * double(x - w) / double(e - w);
            else if (w >= 0)
                h = row[w];
            else if (e < punched.width)
                h = row[e];
            largest = std::max(
                largest,
                std::abs(h - punched.truth[static_cast<std::size_t>(y * punched.width + x)]));
        }
    }
    return largest;
}

}  // namespace

// A membrane reproduces a plane (it is harmonic), through a void wider than a patch of the
// default 257 samples: the pyramid-based solve converges over a void of any size.
TEST(NoDataFill, FillsAPlaneThroughAVoidLargerThanAPatch) {
    Raster r = sampled(640, 480, [](double x, double y) { return 1000.0 + 0.8 * x - 0.3 * y; });
    punch(r, 100, 60, 420, 400);  // 320 × 340 samples
    std::vector<std::uint8_t> valid(r.heights.size());
    EXPECT_EQ(fillNoData(r.width, r.height, r.heights, valid), 320 * 340);
    EXPECT_EQ(valid[static_cast<std::size_t>(200 * r.width + 200)], 0);
    EXPECT_EQ(valid[0], 1);
    EXPECT_LT(largestError(r, valid), 0.5);  // of up to 500 m across the void
}

// A void across a ridge on a slope (SRTM's voids lie on steep ground): the row fill cuts
// the ridge off, a horizontal curtain from one flank to the other; the membrane takes the rims
// north and south of the void too, where the ridge is, and follows it. Where the void reaches
// the raster's west edge, the row fill copies the east rim across it (a streak, the slope times
// the void's width off); the membrane has the rims north and south.
TEST(NoDataFill, AVoidOnASlopeFollowsItNotTheRow) {
    // 30 m samples rising 0.5 m a metre eastwards, and a ridge 300 m high running north.
    const auto surface = [](double x, double y) {
        return 200.0 + 15.0 * x + 300.0 * std::exp(-std::pow((x - 200.0) / 40.0, 2.0)) +
               0.01 * y * y;
    };
    Raster across = sampled(400, 200, surface);
    punch(across, 100, 92, 300, 108);  // 200 × 16 samples over the ridge
    const double rowLinear = largestRowLinearError(across);
    std::vector<std::uint8_t> valid(across.heights.size());
    fillNoData(across.width, across.height, across.heights, valid);
    const double membrane = largestError(across, valid);
    EXPECT_GT(rowLinear, 290.0);  // the ridge, cut off
    // What a 16-sample void misses of the ridge's curvature across it.
    EXPECT_LT(membrane, 30.0);
    EXPECT_LT(membrane, rowLinear / 10.0);

    Raster edge = sampled(400, 200, surface);
    punch(edge, 0, 40, 100, 65);  // 100 × 25 samples from the west edge
    const double rowLinearAtEdge = largestRowLinearError(edge);
    std::vector<std::uint8_t> edgeValid(edge.heights.size());
    fillNoData(edge.width, edge.height, edge.heights, edgeValid);
    const double membraneAtEdge = largestError(edge, edgeValid);
    EXPECT_GT(rowLinearAtEdge, 1400.0);  // 100 samples × 15 m a sample, less the first one
    // Nothing crosses the raster's edge: at the edge the membrane levels off, over about the
    // void's height (25 samples, 15 m each).
    EXPECT_LT(membraneAtEdge, 25.0 * 15.0);
    EXPECT_LT(membraneAtEdge, rowLinearAtEdge / 8.0);
}

// Voids at a corner and along an edge take the valid rim they have: the fill stays within its
// range (the maximum principle) and meets it without a step.
TEST(NoDataFill, VoidsTouchingTheEdgesTakeTheValidRim) {
    Raster r = sampled(300, 200, [](double x, double y) { return 50.0 + 2.0 * x + 1.0 * y; });
    punch(r, 0, 0, 60, 40);        // the north-west corner
    punch(r, 250, 120, 300, 200);  // the south-east corner
    punch(r, 100, 190, 160, 200);  // along the south edge
    std::vector<std::uint8_t> valid(r.heights.size());
    EXPECT_EQ(fillNoData(r.width, r.height, r.heights, valid), 60 * 40 + 50 * 80 + 60 * 10);
    // The rims' ranges: north-west 50 + 2·[0, 60] + [0, 40]; south-east 50 + 2·[249, 299] +
    // [119, 199]; south 50 + 2·[99, 160] + [189, 199].
    const auto within = [&](std::int64_t x0, std::int64_t y0, std::int64_t x1, std::int64_t y1,
                            float low, float high) {
        for (std::int64_t y = y0; y < y1; ++y)
            for (std::int64_t x = x0; x < x1; ++x) {
                EXPECT_GE(r.at(x, y), low - 0.01f) << x << ", " << y;
                EXPECT_LE(r.at(x, y), high + 0.01f) << x << ", " << y;
            }
    };
    within(0, 0, 60, 40, 50.0f + 40.0f, 50.0f + 120.0f + 40.0f);
    within(250, 120, 300, 200, 50.0f + 498.0f + 119.0f, 50.0f + 598.0f + 199.0f);
    within(100, 190, 160, 200, 50.0f + 198.0f + 189.0f, 50.0f + 320.0f + 199.0f);
    // No step at a rim: next to a valid sample, within a few times the plane's own rise between
    // two samples (2 m east, 1 m south), where the void spans 160 m and more.
    for (std::int64_t y = 0; y < 40; ++y) EXPECT_NEAR(r.at(59, y), r.at(60, y), 8.0);
    for (std::int64_t x = 0; x < 60; ++x) EXPECT_NEAR(r.at(x, 39), r.at(x, 40), 8.0);
    for (std::int64_t x = 100; x < 160; ++x) EXPECT_NEAR(r.at(x, 190), r.at(x, 189), 8.0);
}

// A void whose box holds more than 2^20 samples is solved on a grid coarsened by two and
// interpolated back (memory stays bounded): a plane still comes out as the plane, and over a
// surface beneath, the surface plus the rim's difference.
TEST(NoDataFill, AVoidTooLargeToSolveWholeIsSolvedCoarsened) {
    const auto plane = [](double x, double y) { return 300.0 + 0.5 * x + 0.25 * y; };
    Raster r = sampled(1100, 1100, plane);
    punch(r, 20, 20, 1080, 1080);  // a box of 1062² samples
    std::vector<std::uint8_t> valid(r.heights.size());
    EXPECT_EQ(fillNoData(r.width, r.height, r.heights, valid), 1060 * 1060);
    EXPECT_LT(largestError(r, valid), 0.5);

    Raster over = sampled(1100, 1100, plane);
    punch(over, 20, 20, 1080, 1080);
    // The surface beneath: 40 m lower, with a bump the fill must follow.
    const SurfaceBeneath beneath = [&](std::int64_t x, std::int64_t y) -> std::optional<double> {
        return plane(double(x), double(y)) - 40.0 + 80.0 * std::sin(double(x) / 90.0);
    };
    std::vector<std::uint8_t> overValid(over.heights.size());
    fillNoData(over.width, over.height, over.heights, overValid, std::nullopt, &beneath);
    double largest = 0.0;  // from the surface beneath, 40 m up
    for (std::int64_t y = 20; y < 1080; ++y)
        for (std::int64_t x = 20; x < 1080; ++x)
            largest = std::max(largest, std::abs(double(over.at(x, y)) - (*beneath(x, y) + 40.0)));
    // The rim's difference is 40 m less the bump there: the fill departs from the surface
    // beneath, 40 m up, by no more than the bump's 80 m (the maximum principle).
    EXPECT_LT(largest, 80.0 + 0.5);
    // And meets the rim without a step, though solved at every other sample.
    for (std::int64_t x = 20; x < 1080; x += 7) {
        EXPECT_NEAR(over.at(x, 20), plane(double(x), 20.0), 3.0) << x;
        EXPECT_NEAR(over.at(x, 1079), plane(double(x), 1079.0), 3.0) << x;
    }
}

// Holes punched in a fine tile over a coarse global grid: each takes the grid's surface plus
// the difference at its rim, so it matches the fine surface to within what the grid's
// resolution misses of it (the fine detail's amplitude), with no step at the rim.
TEST(NoDataFill, HolesFollowTheGridBeneath) {
    // The grid beneath: samples 64 fine samples apart, bilinear between them.
    const auto coarseSample = [](std::int64_t i, std::int64_t j) {
        return 800.0 + 300.0 * std::sin(double(i) * 0.9) * std::cos(double(j) * 0.7);
    };
    constexpr double kStep = 64.0;
    const auto coarse = [&](double x, double y) {
        const double u = x / kStep, v = y / kStep;
        const auto i = static_cast<std::int64_t>(std::floor(u));
        const auto j = static_cast<std::int64_t>(std::floor(v));
        const double fu = u - double(i), fv = v - double(j);
        return (1 - fv) * ((1 - fu) * coarseSample(i, j) + fu * coarseSample(i + 1, j)) +
               fv * ((1 - fu) * coarseSample(i, j + 1) + fu * coarseSample(i + 1, j + 1));
    };
    // The fine tile: the grid's surface 120 m higher (a datum apart), plus detail of ±6 m.
    constexpr double kDetailM = 6.0;
    const auto fine = [&](double x, double y) {
        return coarse(x, y) + 120.0 + kDetailM * std::sin(x * 0.37) * std::sin(y * 0.23);
    };
    Raster r = sampled(512, 384, fine);
    punch(r, 40, 30, 200, 90);     // wide, across several grid cells
    punch(r, 300, 100, 330, 300);  // tall
    punch(r, 480, 200, 512, 260);  // at the east edge
    const double rowLinear = largestRowLinearError(r);
    const SurfaceBeneath beneath = [&](std::int64_t x, std::int64_t y) -> std::optional<double> {
        return coarse(double(x), double(y));
    };
    std::vector<std::uint8_t> valid(r.heights.size());
    fillNoData(r.width, r.height, r.heights, valid, std::nullopt, &beneath);
    // Within the beneath's resolution error of the fine surface: the detail it cannot hold,
    // on both sides of the rim (2 × 6 m), and a little for the spread.
    const double error = largestError(r, valid);
    EXPECT_LT(error, 2.0 * kDetailM + 1.0);
    EXPECT_GT(rowLinear, 4.0 * error);
    // No step at a rim: the fill next to a valid sample is as close as the detail allows.
    for (std::int64_t x = 40; x < 200; ++x)
        EXPECT_NEAR(r.at(x, 30), r.truth[static_cast<std::size_t>(30 * r.width + x)],
                    2.0 * kDetailM);

    // Where the grid beneath does not cover a void, the membrane fills it.
    Raster alone = sampled(512, 384, fine);
    punch(alone, 40, 30, 200, 90);
    const SurfaceBeneath partly = [&](std::int64_t x, std::int64_t y) -> std::optional<double> {
        if (x < 100) return std::nullopt;
        return coarse(double(x), double(y));
    };
    std::vector<std::uint8_t> aloneValid(alone.heights.size());
    fillNoData(alone.width, alone.height, alone.heights, aloneValid, std::nullopt, &partly);
    Raster membrane = sampled(512, 384, fine);
    punch(membrane, 40, 30, 200, 90);
    std::vector<std::uint8_t> membraneValid(membrane.heights.size());
    fillNoData(membrane.width, membrane.height, membrane.heights, membraneValid);
    EXPECT_EQ(alone.heights, membrane.heights);
}

// Nothing to fill from: 0 m (a build refuses such a raster, PyramidBuilderTest).
TEST(NoDataFill, ARasterWithoutAValidSampleIsZero) {
    std::vector<float> heights(12 * 7, kNaN);
    std::vector<std::uint8_t> valid(heights.size());
    EXPECT_EQ(fillNoData(12, 7, heights, valid), 12 * 7);
    EXPECT_EQ(heights, std::vector<float>(heights.size(), 0.0f));
}

TEST(NoDataFill, RoundsToWholeSourceUnits) {
    // A void between 100 and 101 along a row: its fill is 100 or 101, never between.
    std::vector<float> row = {100.0f, kNaN, kNaN, 101.0f};
    std::vector<std::uint8_t> valid(row.size());
    fillNoData(4, 1, row, valid, VerticalTransform{1.0, 0.0});
    EXPECT_EQ(row, (std::vector<float>{100.0f, 100.0f, 101.0f, 101.0f}));

    // The Puget Sound JPEG's units: 8-bit steps of 25.7 m. The fill is a step, exactly as
    // the reader converts one, so the tile is still coded in the source's units.
    const VerticalTransform jpeg{25.7, 0.0};
    const auto step = [&](int v) { return static_cast<float>(double(v) * jpeg.scale); };
    row = {step(10), kNaN, kNaN, kNaN, step(14)};
    valid.resize(row.size());
    fillNoData(5, 1, row, valid, jpeg);
    EXPECT_EQ(row, (std::vector<float>{step(10), step(11), step(12), step(13), step(14)}));
    std::vector<float> tile(9, step(12));
    tile[0] = row[1];
    std::vector<std::uint32_t> codes(tile.size());
    EXPECT_EQ(encodeHeights(tile, 3, codes, HeightUnits{jpeg}).divisor, kSourceUnits);
}

TEST(NoDataFill, OnlyIntegerSourcesHaveWholeUnits) {
    DemInfo info;
    info.vertical = VerticalTransform{0.1, -5.0};
    info.sampleType = "uint16";
    ASSERT_TRUE(wholeSourceUnits(info).has_value());
    EXPECT_EQ(wholeSourceUnits(info)->scale, 0.1);
    info.sampleType = "float32";
    EXPECT_FALSE(wholeSourceUnits(info).has_value());
    info.sampleType = "int16";
    info.resampledFrom = ResampledGrid{};  // warped: its samples are interpolations
    EXPECT_FALSE(wholeSourceUnits(info).has_value());
}
