// Lossless height codes for the shards (docs/pyramid-format.md, "Height codes"; issue 19).
// A tile's float heights become small integers that zstd compresses well (PatchPayload.h
// stores them as byte planes): heights
// that are whole multiples of 1/D metres for a D from a fixed list (int16 SRTM metres: D = 1;
// the Puget Sound PNG's decimetres: D = 10; the procedural terrain's 1/1024 m: D = 1024)
// are stored as those multiples, any other tile as its floats' bits in an order-preserving
// integer map; either way each integer is replaced by its difference from the median edge
// detector's prediction (LOCO-I, Weinberger, Seroussi & Sapiro 2000, §2.3: the median of
// west, north and west + north − north-west), zigzagged so small differences of either
// sign are small codes. Decoding gives back every float bit for bit.
//
// A lossy pyramid (terrain-build --max-error-m δ) first rounds each level's heights to Yusov's
// quantizer (quantizeHeights); its tiles are then whole multiples of the level's step 2δ_l,
// which the codes count (kQuantizerSteps), so the quantized heights too come back bit for bit.
//
// Below the root, a tile may also be predicted from its parent (issue 19): a coarser level
// keeps the finer level's even samples (Yusov & Shevtsov 2011, §4), so a quarter of a
// tile's samples are its parent's and cost a zero code each, and the others lie between
// them. encodeHeights tries the tile alone and two ways of using the parent and keeps the
// one with the smallest codes (HeightPrediction); the decoder then needs the parent's
// decoded heights (parentSamples).
#pragma once

#include "terrain/source/DemReader.h"

#include <cstdint>
#include <span>
#include <vector>

namespace terrain::io {

/// The divisor that says a tile's integers are the source's own units: heights are
/// (float)(v · verticalScale + verticalOffset), as the DEM readers make them (an 8-bit
/// JPEG scaled by 25.7 m is whole multiples of nothing else).
inline constexpr std::uint32_t kSourceUnits = 0xFFFFFFFFU;

/// The divisor that says a tile's integers count its level's quantizer steps: heights are
/// (float)(q · quantizerStep) (a lossy pyramid, HeightUnits::quantizerStep).
inline constexpr std::uint32_t kQuantizerSteps = 0xFFFFFFFEU;

/// What a pyramid's heights may be whole numbers of, besides 1/D metres: from its manifest.
struct HeightUnits {
    VerticalTransform source;    ///< the manifest's vertical transform (kSourceUnits)
    double quantizerStep = 0.0;  ///< 2δ_l of a lossy pyramid's level (kQuantizerSteps); 0: none
};

/// How a tile's integers are predicted (docs/pyramid-format.md, "Height codes"); the payload
/// header records it (PatchPayload.h).
enum class HeightPrediction : std::uint8_t {
    kWithinTile = 0,       ///< the median edge detector on the tile's own samples
    kParentThenEdges = 1,  ///< the parent's samples at odd indices, the median edge elsewhere
    kFromParent = 2,       ///< the parent's samples, their midpoints, then four neighbours' mean
};
inline constexpr int kHeightPredictions = 3;

/// What encodeHeights chose for a tile.
struct HeightEncoding {
    std::uint32_t divisor = 0;
    HeightPrediction prediction = HeightPrediction::kWithinTile;
};

/// Samples per side of a tile's parent samples: a tile of `side` (odd) samples has them at
/// its odd indices 1, 3, …, side − 2.
inline constexpr int parentSamplesSide(int side) { return (side - 1) / 2; }

/// The parent samples of a tile of `side` samples whose level position has parities
/// (childX % 2, childY % 2), gathered from the parent's own tile (same side): the tile's
/// sample (2a + 1, 2b + 1) is the parent's ((childX % 2)·(side − 3)/2 + 1 + a, likewise in
/// y), which the layout's even-sample rule makes equal (docs/pyramid-format.md, "Levels").
void gatherParentSamples(std::span<const float> parentTile, int side, int childXParity,
                         int childYParity, std::vector<float>& out);

/// A tile's own samples at its odd indices: its parent samples in a lossless planar pyramid.
void oddIndexSamples(std::span<const float> tile, int side, std::vector<float>& out);

/// Yusov & Shevtsov 2011, §4, "Quantizing Height Maps": the uniform quantizer with a dead
/// zone, ĥ = ⌊(h + δ)/(2δ)⌋ · 2δ, for `halfStep` δ > 0. Rounds every height in place to
/// (float)(q · 2δ) and returns the largest |ĥ − h| (at most δ, plus half a float ulp of ĥ
/// where the float rounding of q · 2δ adds to it). Heights whose |q| would pass 2^30 are
/// left as they are (exact; such a tile is coded as floats). Any thread.
double quantizeHeights(std::span<float> heights, double halfStep);

/// `heights` (side × side, row-major, finite; side odd) as codes. The divisor D the codes
/// use: kQuantizerSteps when `units` has a quantizer step and every height is a whole
/// number of steps, else kSourceUnits when `units.source` is not the identity and every
/// height is a whole number of its units, else the first of heightDivisors() that makes
/// every height a whole multiple of 1/D, else 0 (the codes are the floats' bits). With
/// `parentSamples` (parentSamplesSide(side)², as the parent stores them; empty: none) the
/// prediction is whichever of the three gives the smallest codes, else kWithinTile. Any
/// thread.
HeightEncoding encodeHeights(std::span<const float> heights, int side,
                             std::span<std::uint32_t> codes, const HeightUnits& units = {},
                             std::span<const float> parentSamples = {});

/// encodeHeights with the one prediction given (tests and benchmarks compare them).
HeightEncoding encodeHeightsWith(HeightPrediction prediction, std::span<const float> heights,
                                 int side, std::span<std::uint32_t> codes,
                                 const HeightUnits& units = {},
                                 std::span<const float> parentSamples = {});

/// The inverse of encodeHeights given its encoding, `units` and, unless the prediction is
/// kWithinTile, the same parent samples (asserted present). Any codes decode to some floats
/// (a damaged tile is caught by the patch checksum, not here). Any thread.
void decodeHeights(std::span<const std::uint32_t> codes, int side, const HeightEncoding& encoding,
                   std::span<float> heights, const HeightUnits& units = {},
                   std::span<const float> parentSamples = {});

/// `h` rounded to the nearest whole number of the source's units, (float)(v · scale +
/// offset) as the DEM readers convert a raw sample: a height kSourceUnits codes exactly.
/// `source.scale` must be finite and non-zero. Any thread.
float roundToSourceUnits(double h, const VerticalTransform& source);

/// The divisors encodeHeights tries, coarsest step first.
std::span<const std::uint32_t> heightDivisors();

}  // namespace terrain::io
