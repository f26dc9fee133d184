// The payload of one patch in a shard (docs/pyramid-format.md, "Patch payloads"): its height
// codes, no-data mask and block errors packed into byte planes and compressed with zstd, as
// the samples of one deep OpenEXR pixel. Byte planes put the codes' always-zero high bytes
// apart from the busy low ones, and zstd decodes several times faster than the zlib of
// OpenEXR's ZIP (issue 19: ≥ 2,500 tiles/s per I/O thread), whose byte-delta predictor
// would also undo the height codes' own prediction.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/pyramid/HeightCodes.h"
#include "terrain/pyramid/PatchErrors.h"

#include <cstdint>
#include <span>
#include <vector>

namespace terrain::io::shard {

/// The largest zstd level a writer may use (the higher "ultra" levels need far more memory).
inline constexpr int kMaxCompressionLevel = 19;

/// What a shard's payloads hold: tileSamples² codes, as many mask flags if the pyramid has
/// no-data, blocksPerSide² block errors.
struct PayloadShape {
    int tileSamples = 0;
    int blocksPerSide = 0;
    bool withMask = false;
};

/// One patch as packed: `codes` (tileSamples², HeightCodes.h) and the prediction they use,
/// `valid` (tileSamples² flags, 0 or 1, or empty without a mask) and `halfLambdas`
/// (blocksPerSide² × λ(1..4) as HALF bits, block by block). `level` 0 stores the bytes as
/// they are, 1 … kMaxCompressionLevel compresses them with zstd at that level (stored anyway
/// where zstd would not shrink them). Writes the payload's 32-bit samples to `words`. Any
/// thread.
void packPatchPayload(std::span<const std::uint32_t> codes, HeightPrediction prediction,
                      std::span<const std::uint8_t> valid,
                      std::span<const std::uint16_t> halfLambdas, int level,
                      std::vector<std::uint32_t>& words);

/// The inverse: fills codes, prediction, valid (empty without a mask) and blockErrors (the
/// halves as floats). A payload that is not one a writer makes for `shape` is an Error
/// saying what is wrong with it (without a file name), never a crash. Any thread.
Status unpackPatchPayload(std::span<const std::uint32_t> words, const PayloadShape& shape,
                          std::vector<std::uint32_t>& codes, HeightPrediction& prediction,
                          std::vector<std::uint8_t>& valid, std::vector<BlockErrors>& blockErrors);

/// The most 32-bit samples a payload of `shape` can take: a reader refuses a pixel that
/// claims more before it allocates anything for it.
std::size_t maxPayloadWords(const PayloadShape& shape);

}  // namespace terrain::io::shard
