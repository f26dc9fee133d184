// The no-data fill (docs/pyramid-format.md, "No-data"): row-linear, and rounded to the
// source's units when the source stores whole numbers, so a tile with a filled void keeps
// one height unit (HeightCodes.h).
#include "terrain/io/HeightCodes.h"
#include "terrain/io/NoDataFill.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
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
