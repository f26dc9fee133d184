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
#pragma once

#include "terrain/io/DemReader.h"

#include <cstdint>
#include <span>

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

/// Yusov & Shevtsov 2011, §4, "Quantizing Height Maps": the uniform quantizer with a dead
/// zone, ĥ = ⌊(h + δ)/(2δ)⌋ · 2δ, for `halfStep` δ > 0. Rounds every height in place to
/// (float)(q · 2δ) and returns the largest |ĥ − h| (at most δ, plus half a float ulp of ĥ
/// where the float rounding of q · 2δ adds to it). Heights whose |q| would pass 2^30 are
/// left as they are (exact; such a tile is coded as floats). Any thread.
double quantizeHeights(std::span<float> heights, double halfStep);

/// `heights` (side × side, row-major, finite) as codes; returns the divisor D the codes
/// use: kQuantizerSteps when `units` has a quantizer step and every height is a whole
/// number of steps, else kSourceUnits when `units.source` is not the identity and every
/// height is a whole number of its units, else the first of heightDivisors() that makes
/// every height a whole multiple of 1/D, else 0 (the codes are the floats' bits). Any thread.
std::uint32_t encodeHeights(std::span<const float> heights, int side,
                            std::span<std::uint32_t> codes, const HeightUnits& units = {});

/// The inverse of encodeHeights given its divisor and `units`. Any codes decode to some
/// floats (a damaged tile is caught by the patch checksum, not here). Any thread.
void decodeHeights(std::span<const std::uint32_t> codes, int side, std::uint32_t divisor,
                   std::span<float> heights, const HeightUnits& units = {});

/// `h` rounded to the nearest whole number of the source's units, (float)(v · scale +
/// offset) as the DEM readers convert a raw sample: a height kSourceUnits codes exactly.
/// `source.scale` must be finite and non-zero. Any thread.
float roundToSourceUnits(double h, const VerticalTransform& source);

/// The divisors encodeHeights tries, coarsest step first.
std::span<const std::uint32_t> heightDivisors();

}  // namespace terrain::io
