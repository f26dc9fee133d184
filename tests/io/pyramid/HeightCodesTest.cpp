// Height codes (issue 19): every tile decodes to its floats bit for bit, whatever they are;
// the divisor is the coarsest step the heights are whole multiples of; and smooth terrain
// becomes small codes, which is what makes the shards compress.
#include "terrain/pyramid/HeightCodes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <random>
#include <span>
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

// Decodes `codes` and counts the samples that do not come back with the same bits.
int differingAfterDecoding(const std::vector<float>& heights,
                           const std::vector<std::uint32_t>& codes, const HeightEncoding& encoding,
                           const HeightUnits& units, std::span<const float> parent) {
    std::vector<float> decoded(heights.size());
    decodeHeights(codes, kSide, encoding, decoded, units, parent);
    int differing = 0;
    for (std::size_t i = 0; i < heights.size(); ++i)
        if (std::bit_cast<std::uint32_t>(decoded[i]) != std::bit_cast<std::uint32_t>(heights[i])) {
            if (++differing <= 3)
                ADD_FAILURE() << "sample " << i << ": " << heights[i] << " came back as "
                              << decoded[i];
        }
    return differing;
}

// Encodes and decodes `heights`; returns the divisor, failing the test unless every float
// comes back with the same bits. Every prediction from a parent is round-tripped too, with
// the tile's own odd-index samples as the parent's (a lossless pyramid) and with a parent
// whose samples are not the tile's (a lossy one's coarser steps, or anything).
std::uint32_t roundTrip(const std::vector<float>& heights,
                        std::vector<std::uint32_t>* codesOut = nullptr,
                        const HeightUnits& units = {}) {
    std::vector<std::uint32_t> codes(heights.size());
    const HeightEncoding encoding = encodeHeights(heights, kSide, codes, units);
    EXPECT_EQ(encoding.prediction, HeightPrediction::kWithinTile);  // no parent to use
    EXPECT_EQ(differingAfterDecoding(heights, codes, encoding, units, {}), 0);
    if (codesOut != nullptr) *codesOut = codes;

    std::vector<float> own, foreign;
    oddIndexSamples(heights, kSide, own);
    foreign = own;
    for (std::size_t k = 0; k < foreign.size(); ++k)
        foreign[k] = k % 3 == 0 ? std::nextafter(foreign[k] * 1.01f, 0.0f)
                                : static_cast<float>(k % 7) - 3.0f;
    for (const std::vector<float>* parent : {&own, &foreign})
        for (int p = 0; p < kHeightPredictions; ++p) {
            SCOPED_TRACE(::testing::Message()
                         << "prediction " << p << ", " << (parent == &own ? "own" : "foreign")
                         << " parent samples");
            std::vector<std::uint32_t> predicted(heights.size());
            const HeightEncoding with = encodeHeightsWith(static_cast<HeightPrediction>(p), heights,
                                                          kSide, predicted, units, *parent);
            EXPECT_EQ(with.divisor, encoding.divisor);
            EXPECT_EQ(differingAfterDecoding(heights, predicted, with, units, *parent), 0);
        }
    return encoding.divisor;
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

// Below the root a tile's odd-index samples are its parent's (the coarser level keeps the
// even samples): with them, a quarter of the codes are zeros and the rest are predicted
// from both sides, so the tile costs fewer bits than predicted from itself.
TEST(HeightCodesTest, AParentsSamplesMakeSmallerCodes) {
    const std::vector<float> metres = tile([](int x, int y) { return std::round(hills(x, y)); });
    std::vector<std::uint32_t> alone(metres.size()), withParent(metres.size());
    encodeHeights(metres, kSide, alone, {});
    std::vector<float> parent;
    oddIndexSamples(metres, kSide, parent);
    const HeightEncoding encoding = encodeHeights(metres, kSide, withParent, {}, parent);
    EXPECT_NE(encoding.prediction, HeightPrediction::kWithinTile);
    for (int j = 1; j < kSide; j += 2)
        for (int i = 1; i < kSide; i += 2)
            ASSERT_EQ(withParent[static_cast<std::size_t>(j * kSide + i)], 0U) << i << ", " << j;
    const auto bits = [](const std::vector<std::uint32_t>& codes) {
        double sum = 0.0;
        for (const std::uint32_t c : codes) sum += std::bit_width(c);
        return sum;
    };
    EXPECT_LT(bits(withParent), 0.8 * bits(alone));
}

// gatherParentSamples reads the parent's tile where the layout puts a child's even samples:
// for a level raster and its coarser level (every other sample), each of the four children
// of a parent gets exactly its own odd-index samples, apron and overhang included.
TEST(HeightCodesTest, ParentSamplesFollowTheLayout) {
    for (const int quads : {4, 8, 128}) {
        SCOPED_TRACE(quads);
        const int side = quads + 3;
        const int levelSamples = 2 * quads + 1;  // two patches a side
        // Samples beyond the raster take the nearest one, in finest coordinates.
        const auto fine = [&](std::int64_t x, std::int64_t y) {
            x = std::clamp<std::int64_t>(x, 0, levelSamples - 1);
            y = std::clamp<std::int64_t>(y, 0, levelSamples - 1);
            return static_cast<float>(x * 1000 + y);
        };
        const auto coarse = [&](std::int64_t x, std::int64_t y) { return fine(2 * x, 2 * y); };
        const auto patchTile = [&](const auto& level, int px, int py) {
            std::vector<float> t;
            for (int j = 0; j < side; ++j)
                for (int i = 0; i < side; ++i)
                    t.push_back(
                        level(std::int64_t{px} * quads - 1 + i, std::int64_t{py} * quads - 1 + j));
            return t;
        };
        const std::vector<float> parent = patchTile(coarse, 0, 0);
        for (int py = 0; py < 2; ++py)
            for (int px = 0; px < 2; ++px) {
                std::vector<float> gathered, own;
                gatherParentSamples(parent, side, px, py, gathered);
                oddIndexSamples(patchTile(fine, px, py), side, own);
                EXPECT_EQ(gathered, own) << "child " << px << ", " << py;
            }
    }
}

}  // namespace
}  // namespace terrain::io
