// PyramidLayout: the addressing arithmetic of the on-disk pyramid (docs/pyramid-format.md):
// levels, patches, their samples in DEM coordinates, shards and their paths. Pure math,
// shared by the builder, the reader and the runtime.
#pragma once

#include "terrain/base/Result.h"

#include <cstdint>
#include <filesystem>

namespace terrain::io {

struct PatchId {
    int level = 0;
    std::int64_t x = 0;  ///< patch column within the level
    std::int64_t y = 0;  ///< patch row within the level
    bool operator==(const PatchId&) const = default;
};

struct ShardId {
    int level = 0;
    std::int64_t x = 0;
    std::int64_t y = 0;
    bool operator==(const ShardId&) const = default;
};

class PyramidLayout {
public:
    static constexpr int kDefaultPatchSamples = 129;
    /// 16 × 16 blocks of 8 quads in a 129 patch. Yusov §6 uses 8 × 8 blocks of 16; blocks of
    /// 8 draw 38–49 % fewer triangles at the same measured error on the benchmark flights at
    /// ε = 1, 2 px (docs/accuracy.md, "Block size"): a block's inner level is set by its
    /// worst sample, and a smaller block follows the terrain more closely.
    static constexpr int kDefaultBlockQuads = 8;
    static constexpr int kDefaultShardPatches = 16;
    static constexpr int kMinPatchSamples = 5;      // 2^2 + 1
    static constexpr int kMaxPatchSamples = 16385;  // 2^14 + 1
    static constexpr int kMaxShardPatches = 4096;
    /// Largest block: a block's finest tessellation factor is its quads, and GL guarantees
    /// factors up to 64 (MAX_TESS_GEN_LEVEL).
    static constexpr int kMaxBlockQuads = 64;
    /// Largest raster side: 2^40 + 1 samples (a 1 cm grid around the equator).
    static constexpr std::int64_t kMaxRasterSamples = (std::int64_t{1} << 40) + 1;

    /// Checks the parameters: patchSamples = 2^n + 1 (2 ≤ n ≤ 14), blockQuads a power of
    /// two dividing patchSamples − 1 and at most kMaxBlockQuads, 1 ≤ shardPatches ≤
    /// kMaxShardPatches (and the shard's heights part under 2^30 pixels a side), raster from 2 × 2
    /// to kMaxRasterSamples a side, shard indices that fit an int32 (OpenEXR's v2i attribute). The
    /// Error says which parameter is wrong and what it may be.
    static Result<PyramidLayout> create(std::int64_t rasterWidth, std::int64_t rasterHeight,
                                        int patchSamples = kDefaultPatchSamples,
                                        int blockQuads = kDefaultBlockQuads,
                                        int shardPatches = kDefaultShardPatches);

    std::int64_t rasterWidth() const { return m_rasterWidth; }
    std::int64_t rasterHeight() const { return m_rasterHeight; }
    int patchSamples() const { return m_patchSamples; }  ///< N = 2^n + 1
    int patchQuads() const { return m_patchSamples - 1; }
    int apronSamples() const { return 1; }
    int tileSamples() const { return m_patchSamples + 2; }  ///< N + 2 with the apron
    int blockQuads() const { return m_blockQuads; }
    int blocksPerSide() const { return patchQuads() / m_blockQuads; }
    int shardPatches() const { return m_shardPatches; }
    int finestLevel() const { return m_finestLevel; }
    int levelCount() const { return m_finestLevel + 1; }

    /// DEM samples between two samples of `level`: 2^(finest − level).
    std::int64_t levelStep(int level) const { return std::int64_t{1} << (m_finestLevel - level); }
    std::int64_t patchesX(int level) const;
    std::int64_t patchesY(int level) const;
    std::int64_t shardsX(int level) const;
    std::int64_t shardsY(int level) const;
    /// Samples per row/column of the level's padded raster: patches · (N − 1) + 1.
    std::int64_t levelSamplesX(int level) const { return patchesX(level) * patchQuads() + 1; }
    std::int64_t levelSamplesY(int level) const { return patchesY(level) * patchQuads() + 1; }

    std::int64_t patchCount(int level) const;  ///< patchesX · patchesY
    std::int64_t shardCount(int level) const;  ///< shardsX · shardsY

    bool contains(const PatchId& id) const;
    bool contains(const ShardId& s) const;
    ShardId shardOf(const PatchId& id) const;  ///< id must be contained
    /// Patches of the shard: [firstX, firstX + countX) × [firstY, firstY + countY).
    std::int64_t shardFirstX(const ShardId& s) const { return s.x * m_shardPatches; }
    std::int64_t shardFirstY(const ShardId& s) const { return s.y * m_shardPatches; }
    int shardCountX(const ShardId& s) const;  ///< s must be contained
    int shardCountY(const ShardId& s) const;
    /// "L<level>/<sy>/<sx>.exr", relative to the pyramid folder.
    std::filesystem::path shardPath(const ShardId& s) const;

    /// Level sample of the patch's north-west sample (without apron): (x·(N−1), y·(N−1)).
    std::int64_t patchOriginX(const PatchId& id) const { return id.x * patchQuads(); }
    std::int64_t patchOriginY(const PatchId& id) const { return id.y * patchQuads(); }

    bool operator==(const PyramidLayout&) const = default;

private:
    std::int64_t m_rasterWidth = 0;
    std::int64_t m_rasterHeight = 0;
    int m_patchSamples = kDefaultPatchSamples;
    int m_blockQuads = kDefaultBlockQuads;
    int m_shardPatches = kDefaultShardPatches;
    int m_finestLevel = 0;
    std::int64_t m_finestPatchesX = 1;  // patchesX(finestLevel)
    std::int64_t m_finestPatchesY = 1;
};

}  // namespace terrain::io
