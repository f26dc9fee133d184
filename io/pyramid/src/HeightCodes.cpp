#include "terrain/pyramid/HeightCodes.h"

#include "terrain/base/Assert.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
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

std::uint32_t zigzag(std::int32_t r) {
    return (static_cast<std::uint32_t>(r) << 1U) ^ static_cast<std::uint32_t>(r >> 31);
}

std::int32_t unzigzag(std::uint32_t z) {
    return static_cast<std::int32_t>((z >> 1U) ^ (0U - (z & 1U)));
}

// The integer a float stands for under `divisor`, clamped to ±2^31 (a prediction only: a
// parent sample need not be a whole number of the tile's units).
std::int64_t integerOf(float h, std::uint32_t divisor, const HeightUnits& units) {
    if (divisor == 0) return orderedBits(h);
    constexpr double kClamp = 2147483648.0;
    const double m = std::nearbyint(toReal(h, divisor, units));
    return std::abs(m) <= kClamp ? static_cast<std::int64_t>(m) : 0;
}

// The parent samples as integers in the tile's units (integerOf), in a per-thread buffer.
const std::int64_t* parentIntegers(std::span<const float> parentSamples, std::uint32_t divisor,
                                   const HeightUnits& units) {
    thread_local std::vector<std::int64_t> grid;
    grid.resize(parentSamples.size());
    for (std::size_t k = 0; k < parentSamples.size(); ++k)
        grid[k] = integerOf(parentSamples[k], divisor, units);
    return grid.data();
}

// The parent samples whose mean predicts index i of a tile (one axis): its own parent
// sample at an odd index, the two around it at an even one, the one inside at the edges.
struct ParentSpan {
    int first = 0, count = 1;
};

inline ParentSpan parentSpan(int i, int gridSide) {
    if (i % 2 == 1) return {(i - 1) / 2, 1};
    if (i == 0) return {0, 1};
    if (i / 2 >= gridSide) return {gridSide - 1, 1};
    return {i / 2 - 1, 2};
}

// The rounded mean of the parent integers over ys × xs (1, 2 or 4 of them).
inline std::int64_t parentMean(const std::int64_t* grid, int gridSide, ParentSpan xs,
                               ParentSpan ys) {
    std::int64_t sum = 0;
    for (int b = 0; b < ys.count; ++b)
        for (int a = 0; a < xs.count; ++a) sum += grid[(ys.first + b) * gridSide + xs.first + a];
    const int n = xs.count * ys.count;
    return n == 1 ? sum : n == 2 ? (sum + 1) >> 1 : (sum + 2) >> 2;
}

// kFromParent's last pass: an interior sample with both indices even, from the mean of its
// four neighbours, all of which the parent predicted.
inline bool fromNeighbours(int i, int j, int side) {
    return i % 2 == 0 && j % 2 == 0 && i > 0 && j > 0 && i < side - 1 && j < side - 1;
}

inline std::int64_t neighbourMean(const std::int32_t* v, int side, int i, int j) {
    const std::int32_t* at = v + static_cast<std::ptrdiff_t>(j) * side + i;
    return (std::int64_t{at[-1]} + at[1] + at[-side] + at[side] + 2) >> 2;
}

// Every sample's prediction under `prediction`, in an order the decoder can follow:
// visit(k, predicted) for sample k = j·side + i once every sample its prediction reads has
// been visited (raster order; for kFromParent, every sample but the fromNeighbours ones, then
// those), `v` holding the samples visited so far. The encoder's and the decoder's hot loop,
// a loop of its own per prediction (no switch and no parent-span division a sample).
template <typename Visit>
void forEachPrediction(HeightPrediction prediction, const std::int32_t* v, int side,
                       const std::int64_t* grid, Visit&& visit) {
    const int gridSide = parentSamplesSide(side);
    const auto n = static_cast<std::size_t>(side);
    if (prediction == HeightPrediction::kFromParent) {
        thread_local std::vector<ParentSpan> spans;
        spans.resize(n);
        for (int i = 0; i < side; ++i) spans[static_cast<std::size_t>(i)] = parentSpan(i, gridSide);
        for (int j = 0; j < side; ++j)
            for (int i = 0; i < side; ++i)
                if (!fromNeighbours(i, j, side))
                    visit(static_cast<std::size_t>(j) * n + static_cast<std::size_t>(i),
                          parentMean(grid, gridSide, spans[static_cast<std::size_t>(i)],
                                     spans[static_cast<std::size_t>(j)]));
        for (int j = 2; j < side - 1; j += 2)
            for (int i = 2; i < side - 1; i += 2)
                visit(static_cast<std::size_t>(j) * n + static_cast<std::size_t>(i),
                      neighbourMean(v, side, i, j));
        return;
    }
    // Row by row: the west neighbour on the first row (0 for the first sample), the north one
    // on the first column, the median edge detector inside; kParentThenEdges takes the
    // parent's sample at odd (i, j) instead.
    const bool parentSamples = prediction == HeightPrediction::kParentThenEdges;
    visit(std::size_t{0}, std::int64_t{0});
    for (std::size_t x = 1; x < n; ++x) visit(x, std::int64_t{v[x - 1]});
    for (int y = 1; y < side; ++y) {
        const std::size_t k = static_cast<std::size_t>(y) * n;
        const std::int32_t* row = v + k;
        const std::int32_t* north = row - side;
        visit(k, std::int64_t{north[0]});
        if (parentSamples && y % 2 == 1) {
            const std::int64_t* parents = grid + static_cast<std::ptrdiff_t>(y / 2) * gridSide;
            for (std::size_t x = 1; x < n; ++x)
                visit(k + x,
                      x % 2 == 1 ? parents[x / 2] : medianEdge(row[x - 1], north[x], north[x - 1]));
        } else {
            for (std::size_t x = 1; x < n; ++x)
                visit(k + x, medianEdge(row[x - 1], north[x], north[x - 1]));
        }
    }
}

std::uint32_t residualCode(std::int32_t value, std::int64_t prediction) {
    return zigzag(static_cast<std::int32_t>(static_cast<std::uint32_t>(value) -
                                            static_cast<std::uint32_t>(prediction)));
}

std::int32_t addResidual(std::int64_t prediction, std::uint32_t code) {
    return static_cast<std::int32_t>(static_cast<std::uint32_t>(prediction) +
                                     static_cast<std::uint32_t>(unzigzag(code)));
}

// The codes of every sample of a tile under `prediction`, and what zstd will roughly pay
// for them: the bits of each.
std::uint64_t codeTile(HeightPrediction prediction, const std::int32_t* v, int side,
                       const std::int64_t* grid, std::uint32_t* codes) {
    std::uint64_t bits = 0;
    forEachPrediction(prediction, v, side, grid, [&](std::size_t k, std::int64_t predicted) {
        const std::uint32_t code = residualCode(v[k], predicted);
        codes[k] = code;
        bits += static_cast<std::uint64_t>(std::bit_width(code));
    });
    return bits;
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

void gatherParentSamples(std::span<const float> parentTile, int side, int childXParity,
                         int childYParity, std::vector<float>& out) {
    const int gridSide = parentSamplesSide(side);
    const int half = (side - 3) / 2;  // a patch's quads over two
    TERRAIN_ASSERT(parentTile.size() == static_cast<std::size_t>(side) * side,
                   "gatherParentSamples: the parent's side × side heights");
    out.resize(static_cast<std::size_t>(gridSide) * gridSide);
    for (int b = 0; b < gridSide; ++b)
        std::copy_n(parentTile.data() +
                        static_cast<std::ptrdiff_t>(childYParity * half + 1 + b) * side +
                        childXParity * half + 1,
                    gridSide, out.data() + static_cast<std::ptrdiff_t>(b) * gridSide);
}

void oddIndexSamples(std::span<const float> tile, int side, std::vector<float>& out) {
    const int gridSide = parentSamplesSide(side);
    out.resize(static_cast<std::size_t>(gridSide) * gridSide);
    for (int b = 0; b < gridSide; ++b)
        for (int a = 0; a < gridSide; ++a)
            out[static_cast<std::size_t>(b * gridSide + a)] =
                tile[static_cast<std::size_t>((2 * b + 1) * side + 2 * a + 1)];
}

namespace {

// encodeHeights, trying the predictions in [first, last] (those from the parent only with
// its samples).
HeightEncoding encodeTrying(std::span<const float> heights, int side,
                            std::span<std::uint32_t> codes, const HeightUnits& units,
                            std::span<const float> parentSamples, int first, int last) {
    const auto count = static_cast<std::size_t>(side) * static_cast<std::size_t>(side);
    const int gridSide = parentSamplesSide(side);
    TERRAIN_ASSERT(side % 2 == 1 && heights.size() == count && codes.size() == count,
                   "encodeHeights: side × side heights and codes, side odd");
    TERRAIN_ASSERT(parentSamples.empty() ||
                       parentSamples.size() == static_cast<std::size_t>(gridSide) * gridSide,
                   "encodeHeights: parentSamplesSide(side)² parent samples");
    thread_local std::vector<std::int32_t> integers;
    integers.resize(count);
    std::int32_t* values = integers.data();
    HeightEncoding encoding;
    const VerticalTransform& source = units.source;
    const bool scaled = source.scale != 1.0 || source.offset != 0.0;
    const bool quantized = units.quantizerStep > 0.0 && std::isfinite(units.quantizerStep);
    if (quantized && toIntegers(heights, kQuantizerSteps, units, values)) {
        encoding.divisor = kQuantizerSteps;
    } else if (scaled && source.scale != 0.0 && toIntegers(heights, kSourceUnits, units, values)) {
        encoding.divisor = kSourceUnits;
    } else {
        const auto fits = std::find_if(kDivisors.begin(), kDivisors.end(), [&](std::uint32_t d) {
            return toIntegers(heights, d, units, values);
        });
        if (fits != kDivisors.end()) {
            encoding.divisor = *fits;
        } else {
            for (std::size_t i = 0; i < count; ++i) values[i] = orderedBits(heights[i]);
        }
    }
    const std::int64_t* grid = parentIntegers(parentSamples, encoding.divisor, units);

    // Every prediction the tile may use, coded; the one with the fewest bits is kept.
    thread_local std::vector<std::uint32_t> candidate;
    candidate.resize(count);
    std::uint64_t fewest = std::numeric_limits<std::uint64_t>::max();
    if (parentSamples.empty()) last = 0;
    for (int p = first; p <= last; ++p) {
        const auto prediction = static_cast<HeightPrediction>(p);
        const std::uint64_t bits = codeTile(prediction, values, side, grid, candidate.data());
        if (bits < fewest) {
            fewest = bits;
            encoding.prediction = prediction;
            std::copy(candidate.begin(), candidate.end(), codes.begin());
        }
    }
    return encoding;
}

}  // namespace

HeightEncoding encodeHeights(std::span<const float> heights, int side,
                             std::span<std::uint32_t> codes, const HeightUnits& units,
                             std::span<const float> parentSamples) {
    return encodeTrying(heights, side, codes, units, parentSamples, 0, kHeightPredictions - 1);
}

HeightEncoding encodeHeightsWith(HeightPrediction prediction, std::span<const float> heights,
                                 int side, std::span<std::uint32_t> codes, const HeightUnits& units,
                                 std::span<const float> parentSamples) {
    TERRAIN_ASSERT(prediction == HeightPrediction::kWithinTile || !parentSamples.empty(),
                   "encodeHeightsWith: a parent prediction needs the parent samples");
    const int p = static_cast<int>(prediction);
    return encodeTrying(heights, side, codes, units, parentSamples, p, p);
}

void decodeHeights(std::span<const std::uint32_t> codes, int side, const HeightEncoding& encoding,
                   std::span<float> heights, const HeightUnits& units,
                   std::span<const float> parentSamples) {
    const auto count = static_cast<std::size_t>(side) * static_cast<std::size_t>(side);
    const int gridSide = parentSamplesSide(side);
    TERRAIN_ASSERT(heights.size() == count && codes.size() == count,
                   "decodeHeights: side × side codes and heights");
    const HeightPrediction prediction = encoding.prediction;
    TERRAIN_ASSERT(prediction == HeightPrediction::kWithinTile ||
                       parentSamples.size() == static_cast<std::size_t>(gridSide) * gridSide,
                   "decodeHeights: a parent prediction needs the parent samples");
    const std::uint32_t divisor = encoding.divisor;
    // The integers first, then the heights they stand for.
    thread_local std::vector<std::int32_t> scratch;
    scratch.resize(count);
    std::int32_t* values = scratch.data();
    const std::int64_t* grid = prediction == HeightPrediction::kWithinTile
                                   ? nullptr
                                   : parentIntegers(parentSamples, divisor, units);
    forEachPrediction(prediction, values, side, grid, [&](std::size_t k, std::int64_t predicted) {
        values[k] = addResidual(predicted, codes[k]);
    });
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
