#include "terrain/io/HeightCodes.h"

#include "terrain/base/Assert.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <vector>

namespace terrain::io {
namespace {

// 1/D metres: whole metres, halves … of binary fractions, decimetres, centimetres and
// millimetres; the binary ones up to 1/65536 m, finer than any DEM's vertical resolution.
constexpr std::array<std::uint32_t, 19> kDivisors = {
    1, 2, 4, 8, 10, 16, 20, 32, 64, 100, 128, 256, 512, 1000, 1024, 2048, 4096, 16384, 65536};

// Multiples beyond ±2^30 are left to the float-bits codes, so every prediction and
// difference below stays far inside 64-bit arithmetic and every multiple inside int32.
constexpr double kLargestMultiple = 1073741824.0;

float fromMultiple(std::int32_t multiple, std::uint32_t divisor) {
    return static_cast<float>(double(multiple) / double(divisor));
}

// As the DEM readers convert a raw sample (DemSampleConversion.h).
float fromSourceUnits(double v, const VerticalTransform& source) {
    return static_cast<float>(v * source.scale + source.offset);
}

float fromSteps(std::int32_t q, double step) { return static_cast<float>(double(q) * step); }

float fromInteger(std::int32_t v, std::uint32_t divisor, const HeightUnits& units) {
    switch (divisor) {
        case kSourceUnits:
            return fromSourceUnits(v, units.source);
        case kQuantizerSteps:
            return fromSteps(v, units.quantizerStep);
        default:
            return fromMultiple(v, divisor);
    }
}

double toReal(float h, std::uint32_t divisor, const HeightUnits& units) {
    switch (divisor) {
        case kSourceUnits:
            return (double(h) - units.source.offset) / units.source.scale;
        case kQuantizerSteps:
            return double(h) / units.quantizerStep;
        default:
            return double(h) * double(divisor);
    }
}

// Writes the integer of every height under `divisor` to `values`; false, stopping early, as
// soon as one is out of range or does not give its height back bit for bit.
bool toIntegers(std::span<const float> heights, std::uint32_t divisor, const HeightUnits& units,
                std::int32_t* values) {
    for (std::size_t i = 0; i < heights.size(); ++i) {
        const float h = heights[i];
        const double m = std::nearbyint(toReal(h, divisor, units));
        if (!(std::abs(m) <= kLargestMultiple)) return false;
        values[i] = static_cast<std::int32_t>(m);
        if (std::bit_cast<std::uint32_t>(fromInteger(values[i], divisor, units)) !=
            std::bit_cast<std::uint32_t>(h))
            return false;
    }
    return true;
}

// Floats as integers in the same order (negative floats have their magnitude bits
// flipped), so neighbouring heights are neighbouring integers.
std::int32_t orderedBits(float h) {
    auto i = std::bit_cast<std::int32_t>(h);
    return i < 0 ? i ^ 0x7fffffff : i;
}

float fromOrderedBits(std::int32_t i) { return std::bit_cast<float>(i < 0 ? i ^ 0x7fffffff : i); }

// LOCO-I's median edge detector (Weinberger et al. 2000, §2.3) from the west (a), north
// (b) and north-west (c) neighbours.
inline std::int64_t medianEdge(std::int64_t a, std::int64_t b, std::int64_t c) {
    const std::int64_t low = std::min(a, b), high = std::max(a, b);
    return c >= high ? low : c <= low ? high : a + b - c;
}

// The prediction of sample (x, y): the median edge detector inside, the west neighbour on
// the first row (0 for the first sample), the north one on the first column.
inline std::int64_t predict(const std::int32_t* v, int side, int x, int y) {
    if (y == 0) return x == 0 ? 0 : v[x - 1];
    const std::int32_t* north = v + static_cast<std::ptrdiff_t>(y - 1) * side;
    if (x == 0) return north[0];
    return medianEdge(north[side + x - 1], north[x], north[x - 1]);
}

std::uint32_t zigzag(std::int32_t r) {
    return (static_cast<std::uint32_t>(r) << 1U) ^ static_cast<std::uint32_t>(r >> 31);
}

std::int32_t unzigzag(std::uint32_t z) {
    return static_cast<std::int32_t>((z >> 1U) ^ (0U - (z & 1U)));
}

}  // namespace

std::span<const std::uint32_t> heightDivisors() { return kDivisors; }

float roundToSourceUnits(double h, const VerticalTransform& source) {
    return fromSourceUnits(std::nearbyint((h - source.offset) / source.scale), source);
}

double quantizeHeights(std::span<float> heights, double halfStep) {
    TERRAIN_ASSERT(halfStep > 0.0 && std::isfinite(halfStep), "quantizeHeights: δ > 0");
    const double step = 2.0 * halfStep;
    double largest = 0.0;
    for (float& h : heights) {
        // §4: Q_l(h) = ⌊(h + δ_l)/(2δ_l)⌋, ĥ = 2δ_l · Q_l(h).
        const double q = std::floor((double(h) + halfStep) / step);
        if (!(std::abs(q) <= kLargestMultiple)) continue;
        const float stored = fromSteps(static_cast<std::int32_t>(q), step);
        largest = std::max(largest, std::abs(double(stored) - double(h)));
        h = stored;
    }
    return largest;
}

std::uint32_t encodeHeights(std::span<const float> heights, int side,
                            std::span<std::uint32_t> codes, const HeightUnits& units) {
    const auto count = static_cast<std::size_t>(side) * static_cast<std::size_t>(side);
    TERRAIN_ASSERT(heights.size() == count && codes.size() == count,
                   "encodeHeights: side × side heights and codes");
    // The integers first (in `codes`, as int32 bits), then their differences in place,
    // from the last sample back, so each prediction still reads original integers.
    auto* values = reinterpret_cast<std::int32_t*>(codes.data());
    std::uint32_t divisor = 0;
    const VerticalTransform& source = units.source;
    const bool scaled = source.scale != 1.0 || source.offset != 0.0;
    const bool quantized = units.quantizerStep > 0.0 && std::isfinite(units.quantizerStep);
    if (quantized && toIntegers(heights, kQuantizerSteps, units, values)) {
        divisor = kQuantizerSteps;
    } else if (scaled && source.scale != 0.0 && toIntegers(heights, kSourceUnits, units, values)) {
        divisor = kSourceUnits;
    } else {
        const auto fits = std::find_if(kDivisors.begin(), kDivisors.end(), [&](std::uint32_t d) {
            return toIntegers(heights, d, units, values);
        });
        if (fits != kDivisors.end()) {
            divisor = *fits;
        } else {
            for (std::size_t i = 0; i < count; ++i) values[i] = orderedBits(heights[i]);
        }
    }
    for (int y = side - 1; y >= 0; --y)
        for (int x = side - 1; x >= 0; --x) {
            const std::size_t i = static_cast<std::size_t>(y * side + x);
            const auto p = static_cast<std::uint32_t>(predict(values, side, x, y));
            const auto residual =
                static_cast<std::int32_t>(static_cast<std::uint32_t>(values[i]) - p);
            codes[i] = zigzag(residual);
        }
    return divisor;
}

void decodeHeights(std::span<const std::uint32_t> codes, int side, std::uint32_t divisor,
                   std::span<float> heights, const HeightUnits& units) {
    const auto count = static_cast<std::size_t>(side) * static_cast<std::size_t>(side);
    TERRAIN_ASSERT(heights.size() == count && codes.size() == count,
                   "decodeHeights: side × side codes and heights");
    // The integers first, then the heights they stand for.
    thread_local std::vector<std::int32_t> scratch;
    scratch.resize(count);
    std::int32_t* values = scratch.data();
    const auto add = [](std::int64_t prediction, std::uint32_t code) {
        return static_cast<std::int32_t>(static_cast<std::uint32_t>(prediction) +
                                         static_cast<std::uint32_t>(unzigzag(code)));
    };
    // predict() unrolled by row, the decoder's hot loop.
    values[0] = add(0, codes[0]);
    for (int x = 1; x < side; ++x) values[x] = add(values[x - 1], codes[x]);
    for (int y = 1; y < side; ++y) {
        std::int32_t* row = values + static_cast<std::ptrdiff_t>(y) * side;
        const std::int32_t* north = row - side;
        const std::uint32_t* in = codes.data() + static_cast<std::ptrdiff_t>(y) * side;
        row[0] = add(north[0], in[0]);
        for (int x = 1; x < side; ++x)
            row[x] = add(medianEdge(row[x - 1], north[x], north[x - 1]), in[x]);
    }
    if (divisor == 0) {
        for (std::size_t i = 0; i < count; ++i) heights[i] = fromOrderedBits(values[i]);
    } else if (divisor == kSourceUnits) {
        for (std::size_t i = 0; i < count; ++i)
            heights[i] = fromSourceUnits(values[i], units.source);
    } else if (divisor == kQuantizerSteps) {
        for (std::size_t i = 0; i < count; ++i)
            heights[i] = fromSteps(values[i], units.quantizerStep);
    } else {
        for (std::size_t i = 0; i < count; ++i) heights[i] = fromMultiple(values[i], divisor);
    }
}

}  // namespace terrain::io
