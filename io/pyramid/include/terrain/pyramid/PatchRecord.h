// PatchRecord: everything the pyramid stores for one patch (docs/pyramid-format.md):
// heights with apron, no-data mask, tessellation-block errors and the per-patch summary.
#pragma once

#include "terrain/pyramid/PatchErrors.h"
#include "terrain/pyramid/PyramidLayout.h"

#include <cstdint>
#include <span>
#include <vector>

namespace terrain::io {

struct PatchInfo {
    bool present = false;    ///< overlaps the DEM
    float minHeight = 0.0f;  ///< of the N × N drawn samples, metres
    float maxHeight = 0.0f;
    float error = 0.0f;               ///< Err(P) = approxError + quantError (Yusov §4)
    float approxError = 0.0f;         ///< Err_Appr(P)
    float quantError = 0.0f;          ///< δ: 0 for lossless float32 storage
    std::uint32_t noDataSamples = 0;  ///< filled or overhanging among the N × N
    std::uint32_t crc32 = 0;          ///< of the stored tiles; set by the shard writer
    /// Globe pyramids (format version 3) only: which of the four children exist, bit
    /// (cy · 2 + cx) for the child at offset (cx, cy). A globe pyramid is sparse, and the LOD
    /// learns from a resident parent where finer data is without asking the disk. Always 0
    /// in a planar pyramid, whose children all exist.
    std::uint8_t presentChildren = 0;
    bool operator==(const PatchInfo&) const = default;
};

struct PatchRecord {
    PatchId id;
    PatchInfo info;
    std::vector<float> heights;            ///< tileSamples² metres, row-major, apron included
    std::vector<std::uint8_t> valid;       ///< tileSamples², 1 valid / 0 filled; empty when the
                                           ///< pyramid has no no-data
    std::vector<BlockErrors> blockErrors;  ///< blocksPerSide², row-major: λ(1..4)
};

/// Sets info's minHeight, maxHeight and noDataSamples from a patch's N × N drawn samples,
/// the apron excluded: the one definition every writer of patches uses. `heights` holds
/// layout.tileSamples()² samples (apron included); `valid` as many flags (0: filled or
/// overhanging, whether or not the pyramid stores a mask), or is empty when every sample
/// is valid.
void summariseDrawnSamples(const PyramidLayout& layout, std::span<const float> heights,
                           std::span<const std::uint8_t> valid, PatchInfo& info);

}  // namespace terrain::io
