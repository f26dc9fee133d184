// Height codes (issue 19): every tile decodes to its floats bit for bit, whatever they are;
// the divisor is the coarsest step the heights are whole multiples of; and smooth terrain
// becomes small codes, which is what makes the shards compress.
#include "terrain/io/HeightCodes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <random>
#include <vector>

namespace terrain::io {
namespace {

constexpr int kSide = 131;

std::vector<float> tile(const std::function<float(int x, int y)>& height) {
    std::vector<float> h;
    for (int y = 0; y < kSide; ++y)
        for (int x = 0; x < kSide; ++x) h.push_back(height(x, y));
    return h;
}

// Encodes and decodes `heights`; returns the divisor, failing the test unless every float
// comes back with the same bits.
std::uint32_t roundTrip(const std::vector<float>& heights,
                        std::vector<std::uint32_t>* codesOut = nullptr,
                        const HeightUnits& units = {}) {
    std::vector<std::uint32_t> codes(heights.size());
    const std::uint32_t divisor = encodeHeights(heights, kSide, codes, units);
    std::vector<float> decoded(heights.size());
    decodeHeights(codes, kSide, divisor, decoded, units);
    int differing = 0;
    for (std::size_t i = 0; i < heights.size(); ++i)
        if (std::bit_cast<std::uint32_t>(decoded[i]) != std::bit_cast<std::uint32_t>(heights[i])) {
            if (++differing <= 3)
                ADD_FAILURE() << "sample " << i << ": " << heights[i] << " came back as "
                              << decoded[i];
        }
    EXPECT_EQ(differing, 0);
    if (codesOut != nullptr) *codesOut = codes;
    return divisor;
}

double meanCode(const std::vector<std::uint32_t>& codes) {
    double sum = 0.0;
    for (const std::uint32_t c : codes) sum += double(c);
    return sum / double(codes.size());
}

float hills(int x, int y) {
    return static_cast<float>(1200.0 + 300.0 * std::sin(x / 13.0) * std::cos(y / 17.0) + 2.0 * y);
}

TEST(HeightCodesTest, WholeMetresDecimetresAndBinaryFractionsAreMultiples) {
    EXPECT_EQ(roundTrip(tile([](int x, int y) { return std::round(hills(x, y)); })), 1U);
    EXPECT_EQ(roundTrip(tile([](int x, int y) { return std::round(hills(x, y)) - 5000.0f; })), 1U);
    // The Puget Sound PNG's heights: 16-bit decimetres times 0.1, as the reader makes them.
    EXPECT_EQ(roundTrip(tile([](int x, int y) {
                  return static_cast<float>(double(std::lround(hills(x, y) * 10.0)) * 0.1);
              })),
              10U);
    EXPECT_EQ(
        roundTrip(tile([](int x, int y) { return std::round(hills(x, y) * 1024.0f) / 1024.0f; })),
        1024U);
    EXPECT_EQ(roundTrip(tile([](int, int) { return 0.0f; })), 1U);
}

// The Puget Sound JPEG: 8-bit samples scaled by 25.7 m, whole multiples of no 1/D.
TEST(HeightCodesTest, ScaledSourcesAreCodedInTheirOwnUnits) {
    const VerticalTransform jpeg{25.7, -3.0};
    const auto scaled = [&](int x, int y) {
        const long raw = std::lround(std::clamp(hills(x, y) / 8.0, 0.0, 255.0));
        return static_cast<float>(double(raw) * jpeg.scale + jpeg.offset);
    };
    std::vector<std::uint32_t> codes;
    EXPECT_EQ(roundTrip(tile(scaled), &codes, {jpeg}), kSourceUnits);
    EXPECT_LT(meanCode(codes), 4.0);  // a few units a sample
    // Without the units the tile is multiples of a finer step (25.7 m steps are also
    // decimetres), in codes hundreds of times larger.
    std::vector<std::uint32_t> finer;
    EXPECT_NE(roundTrip(tile(scaled), &finer), kSourceUnits);
    EXPECT_GT(meanCode(finer), 100.0 * meanCode(codes));
    // A tile with a sample no unit makes (a filled hole's interpolation) falls back.
    EXPECT_NE(roundTrip(tile([&](int x, int y) { return x == 9 && y == 9 ? 1.0f : scaled(x, y); }),
                        nullptr, {jpeg}),
              kSourceUnits);
    // Identity units are the divisor 1.
    EXPECT_EQ(roundTrip(tile([](int x, int y) { return std::round(hills(x, y)); }), nullptr,
                        {VerticalTransform{}}),
              1U);
}

// Yusov & Shevtsov 2011, §4: every height within δ of the source, as (float)(q · 2δ), and the
// codes count q so that the quantized heights come back bit for bit.
TEST(HeightCodesTest, QuantizedHeightsStayWithinHalfAStepAndComeBackExactly) {
    for (const double delta : {1.0, 0.25, 0.3, 7.5}) {
        SCOPED_TRACE(delta);
        const std::vector<float> exact = tile(hills);
        std::vector<float> quantized = exact;
        const double largest = quantizeHeights(quantized, delta);
        double measured = 0.0;
        for (std::size_t i = 0; i < exact.size(); ++i) {
            // A whole number of steps, as a float.
            const double q = std::round(double(quantized[i]) / (2.0 * delta));
            EXPECT_EQ(quantized[i], static_cast<float>(q * 2.0 * delta)) << i;
            measured = std::max(measured, std::abs(double(quantized[i]) - double(exact[i])));
        }
        EXPECT_EQ(largest, measured);
        // Within δ up to half a float ulp of heights below 2048 m.
        EXPECT_LE(largest, delta + 0x1p-13);
        EXPECT_GT(largest, 0.9 * delta);  // hills cross every step's edge somewhere
        std::vector<std::uint32_t> codes;
        EXPECT_EQ(roundTrip(quantized, &codes, {.source = {}, .quantizerStep = 2.0 * delta}),
                  kQuantizerSteps);
        // Coarser than the lossless codes of the same tile (floats of 1/16384 m).
        std::vector<std::uint32_t> lossless;
        roundTrip(exact, &lossless);
        EXPECT_LT(meanCode(codes) * 100.0, meanCode(lossless));
    }
    // The quantizer rounds half up, ⌊(h + δ)/2δ⌋: −1 → −2 and 1 → 2 for δ = 1, 0.999 → 0.
    std::vector<float> edges = {-1.0f, 1.0f, 0.999f, -3.0f, 2.0f};
    EXPECT_EQ(quantizeHeights(edges, 1.0), 1.0);
    EXPECT_EQ(edges, (std::vector<float>{0.0f, 2.0f, 0.0f, -2.0f, 2.0f}));
    // Heights past 2^30 steps are left exact, and the tile is coded by its bits.
    std::vector<float> huge = tile([](int x, int) { return x == 5 ? 1e12f : 100.0f; });
    EXPECT_EQ(quantizeHeights(huge, 1e-3), 0.0);
    EXPECT_EQ(huge[5], 1e12f);
    EXPECT_EQ(roundTrip(huge, nullptr, {.source = {}, .quantizerStep = 2e-3}), 0U);
}

TEST(HeightCodesTest, FloatsAreMultiplesOfTheirSpacing) {
    // Floats from 1024 to 2048 are all multiples of their spacing, 2^-13.
    EXPECT_EQ(roundTrip(tile(hills)), 16384U);
}

TEST(HeightCodesTest, AnyOtherFloatsAreCodedByTheirBits) {
    std::mt19937 random(7);
    const auto anyFinite = [&](int, int) {
        for (;;) {
            const auto h = std::bit_cast<float>(static_cast<std::uint32_t>(random()));
            if (std::isfinite(h)) return h;
        }
    };
    EXPECT_EQ(roundTrip(tile(anyFinite)), 0U);
    // Beyond the multiples' range, the smallest and largest floats, −0 and denormals.
    const std::vector<float> extremes = {1e12f,
                                         -1e12f,
                                         std::numeric_limits<float>::max(),
                                         std::numeric_limits<float>::lowest(),
                                         -0.0f,
                                         std::numeric_limits<float>::denorm_min(),
                                         -std::numeric_limits<float>::denorm_min(),
                                         1.5f};
    EXPECT_EQ(roundTrip(tile([&](int x, int y) {
                  return extremes[static_cast<std::size_t>(x + y) % extremes.size()];
              })),
              0U);
    // One odd sample sends the whole tile to the bits, and it still comes back.
    EXPECT_EQ(roundTrip(tile([](int x, int y) {
                  return x == 70 && y == 3 ? 1e-7f : std::round(hills(x, y));
              })),
              0U);
}

TEST(HeightCodesTest, SmoothTerrainBecomesSmallCodes) {
    std::vector<std::uint32_t> metres, bits;
    roundTrip(tile([](int x, int y) { return std::round(hills(x, y)); }), &metres);
    // Whole metres on slopes of up to 25 m a sample: a few metres off the prediction.
    EXPECT_LT(meanCode(metres), 16.0);
    // Floats finer than 1/65536, coded by their bits (here all between 1 and 2, where the
    // bits are linear in the value): neighbours' bits differ by far less than the bits.
    const auto fine = [](int x, int y) { return 1.5f + (hills(x, y) - 1400.0f) / 2000.0f; };
    EXPECT_EQ(roundTrip(tile(fine), &bits), 0U);
    EXPECT_LT(meanCode(bits), double(std::bit_cast<std::uint32_t>(1.5f)) / 1000.0);
    // A plane of whole metres is predicted all but exactly.
    std::vector<std::uint32_t> plane;
    roundTrip(tile([](int x, int y) { return float(3 * x - 2 * y + 100); }), &plane);
    EXPECT_LT(meanCode(plane), 8.0);
}

}  // namespace
}  // namespace terrain::io
