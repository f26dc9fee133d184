// The no-data fill (docs/pyramid-format.md, "No-data"): row-linear, and rounded to the
// source's units when the source stores whole numbers, so a tile with a filled void keeps
// one height unit (HeightCodes.h).
#include "terrain/pyramid/HeightCodes.h"
#include "terrain/build/NoDataFill.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <optional>
#include <random>
#include <vector>

using namespace terrain::io;

namespace {
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
}

TEST(NoDataFill, InterpolatesAlongTheRow) {
    std::vector<float> row = {100.0f, kNaN, kNaN, 101.0f, kNaN};
    std::vector<std::uint8_t> valid(row.size());
    EXPECT_EQ(fillNoDataRow(row, valid), 3);
    EXPECT_FLOAT_EQ(row[1], 100.0f + 1.0f / 3.0f);
    EXPECT_FLOAT_EQ(row[2], 100.0f + 2.0f / 3.0f);
    EXPECT_EQ(row[4], 101.0f);  // one side only: that sample's value
    EXPECT_EQ(valid, (std::vector<std::uint8_t>{1, 0, 0, 1, 0}));
}

TEST(NoDataFill, RoundsToWholeSourceUnits) {
    std::vector<float> row = {100.0f, kNaN, kNaN, 101.0f};
    std::vector<std::uint8_t> valid(row.size());
    fillNoDataRow(row, valid, VerticalTransform{1.0, 0.0});
    EXPECT_EQ(row, (std::vector<float>{100.0f, 100.0f, 101.0f, 101.0f}));

    // The Puget Sound JPEG's units: 8-bit steps of 25.7 m. The fill is a step, exactly as
    // the reader converts one, so the tile is still coded in the source's units.
    const VerticalTransform jpeg{25.7, 0.0};
    const auto step = [&](int v) { return static_cast<float>(double(v) * jpeg.scale); };
    row = {step(10), kNaN, kNaN, kNaN, step(14)};
    valid.resize(row.size());
    fillNoDataRow(row, valid, jpeg);
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

// A region build fills a window of a row (NoDataFill.h): with the row's nearest valid samples
// beyond the window, every window of every row comes out bit for bit as in the whole row.
TEST(NoDataFill, AWindowFillsAsTheWholeRow) {
    std::mt19937 rng(11);
    for (int trial = 0; trial < 200; ++trial) {
        std::vector<float> row(40);
        for (std::size_t i = 0; i < row.size(); ++i)
            row[i] = rng() % 3 == 0 ? kNaN : static_cast<float>(rng() % 1000) * 0.25f;
        if (trial % 10 == 0) std::fill(row.begin() + 5, row.end() - 3, kNaN);  // long runs
        for (const bool units : {false, true}) {
            const std::optional<VerticalTransform> whole =
                units ? std::optional{VerticalTransform{0.5, 0.0}} : std::nullopt;
            std::vector<float> filled = row;
            std::vector<std::uint8_t> valid(row.size());
            const std::int64_t count = fillNoDataRow(filled, valid, whole);
            std::int64_t windowCount = 0;
            for (std::size_t a = 0; a < row.size(); a += 7) {
                const std::size_t b = std::min(row.size(), a + 7);
                std::vector<float> window(row.begin() + a, row.begin() + b);
                std::vector<std::uint8_t> windowValid(window.size());
                std::optional<RowNeighbour> west, east;
                for (std::size_t k = a; k-- > 0;)
                    if (!std::isnan(row[k])) {
                        west = RowNeighbour{std::int64_t(k) - std::int64_t(a), row[k]};
                        break;
                    }
                for (std::size_t k = b; k < row.size(); ++k)
                    if (!std::isnan(row[k])) {
                        east = RowNeighbour{std::int64_t(k) - std::int64_t(a), row[k]};
                        break;
                    }
                windowCount += fillNoDataWindow(window, windowValid, whole, west, east);
                for (std::size_t i = a; i < b; ++i) {
                    EXPECT_EQ(window[i - a], filled[i]) << "trial " << trial << " sample " << i;
                    EXPECT_EQ(windowValid[i - a], valid[i]);
                }
            }
            EXPECT_EQ(windowCount, count);
        }
    }
}
