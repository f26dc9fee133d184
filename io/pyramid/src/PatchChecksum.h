// The checksum of a stored patch (docs/pyramid-format.md, patchInfo channel crc32): what the
// shard writer stores and the reader verifies, defined once.
#pragma once

#include "terrain/pyramid/PatchErrors.h"
#include "terrain/pyramid/PatchRecord.h"

#include <cstdint>
#include <span>

namespace terrain::io {

/// CRC-32 (zlib's polynomial, initial value 0) over, in this order: the patch's heights
/// (apron included) row by row as little-endian float32; if `valid` is not empty, its mask
/// flags row by row as little-endian halves (1 → 0x3C00, 0 → 0x0000); then λ(1) of every block row
/// by row as little-endian float32, then λ(2), λ(3), λ(4) likewise; then the info's present (uint32
/// 1), minHeight, maxHeight, error, approxError, quantError (float32) and noDataSamples (uint32),
/// little-endian. The info is included because OpenEXR stores a small patchInfo tile uncompressed,
/// where nothing else would notice a damaged bound.
std::uint32_t patchChecksum(std::span<const float> heights, std::span<const std::uint8_t> valid,
                            std::span<const BlockErrors> blockErrors, const PatchInfo& info);

}  // namespace terrain::io
