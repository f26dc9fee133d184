// The addressing arithmetic of the pyramid (docs/pyramid-format.md, "Levels, patches and
// samples" and "Shard files"). Everything is closed-form, so any patch is found in O(1).
#include "terrain/pyramid/PyramidLayout.h"

#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <string>

namespace terrain::io {
namespace {

std::int64_t ceilDiv(std::int64_t a, std::int64_t b) { return (a + b - 1) / b; }

bool isPowerOfTwo(std::int64_t v) { return v > 0 && (v & (v - 1)) == 0; }

// Patches of the finest level along one side: max(1, ceil((samples − 1) / (N − 1))).
std::int64_t finestPatches(std::int64_t samples, int patchQuads) {
    return std::max<std::int64_t>(1, ceilDiv(samples - 1, patchQuads));
}

}  // namespace

Result<PyramidLayout> PyramidLayout::create(std::int64_t rasterWidth, std::int64_t rasterHeight,
                                            int patchSamples, int blockQuads, int shardPatches) {
    if (rasterWidth < 2 || rasterHeight < 2)
        return Error{fmt::format("raster of {} × {} samples: a pyramid needs at least 2 × 2",
                                 rasterWidth, rasterHeight)};
    if (rasterWidth > kMaxRasterSamples || rasterHeight > kMaxRasterSamples)
        return Error{fmt::format("raster of {} × {} samples: at most {} samples a side",
                                 rasterWidth, rasterHeight, kMaxRasterSamples)};
    if (patchSamples < kMinPatchSamples || patchSamples > kMaxPatchSamples ||
        !isPowerOfTwo(patchSamples - 1))
        return Error{fmt::format(
            "patch size {} samples: must be 2^n + 1 with n from 2 to 14 (5, 9, 17, ..., 16385)",
            patchSamples)};
    // A block is drawn with tessellation factors up to its quads, and GL clamps a factor to
    // MAX_TESS_GEN_LEVEL, which GL guarantees only up to 64 (GL 4.5 §11.2.2): a
    // larger block would draw every other sample where its bounds say it draws them all.
    const int largestBlock = std::min(patchSamples - 1, kMaxBlockQuads);
    if (!isPowerOfTwo(blockQuads) || blockQuads > largestBlock)
        return Error{fmt::format(
            "tessellation block of {} quads: must be a power of two from 1 to {} "
            "({})",
            blockQuads, largestBlock,
            largestBlock < kMaxBlockQuads ? "patch size − 1" : "GL's largest tessellation factor")};
    // The shard's heights part is shardPatches·(N + 2) pixels wide: keep it well inside
    // OpenEXR's int32 coordinates.
    const std::int64_t maxShardPatches =
        std::min<std::int64_t>(kMaxShardPatches, (std::int64_t{1} << 30) / (patchSamples + 2));
    if (shardPatches < 1 || shardPatches > maxShardPatches)
        return Error{fmt::format("shard of {} × {} patches: must be from 1 to {} a side",
                                 shardPatches, shardPatches, maxShardPatches)};

    PyramidLayout layout;
    layout.m_rasterWidth = rasterWidth;
    layout.m_rasterHeight = rasterHeight;
    layout.m_patchSamples = patchSamples;
    layout.m_blockQuads = blockQuads;
    layout.m_shardPatches = shardPatches;
    const int quads = patchSamples - 1;
    layout.m_finestPatchesX = finestPatches(rasterWidth, quads);
    layout.m_finestPatchesY = finestPatches(rasterHeight, quads);
    const std::int64_t side = std::max(layout.m_finestPatchesX, layout.m_finestPatchesY);
    int level = 0;
    while ((std::int64_t{1} << level) < side) ++level;
    layout.m_finestLevel = level;
    if (layout.shardsX(level) > std::numeric_limits<std::int32_t>::max() ||
        layout.shardsY(level) > std::numeric_limits<std::int32_t>::max())
        return Error{fmt::format(
            "raster of {} × {} samples in patches of {} and shards of {}: more than 2^31 "
            "shards a side; use larger patches or shards",
            rasterWidth, rasterHeight, patchSamples, shardPatches)};
    return layout;
}

// patchesX(l − 1) = ceil(patchesX(l) / 2) repeated is ceil(patchesX(L) / 2^(L − l)).
std::int64_t PyramidLayout::patchesX(int level) const {
    TERRAIN_ASSERT(level >= 0 && level <= m_finestLevel, "level outside the pyramid");
    return ceilDiv(m_finestPatchesX, levelStep(level));
}

std::int64_t PyramidLayout::patchesY(int level) const {
    TERRAIN_ASSERT(level >= 0 && level <= m_finestLevel, "level outside the pyramid");
    return ceilDiv(m_finestPatchesY, levelStep(level));
}

std::int64_t PyramidLayout::shardsX(int level) const {
    return ceilDiv(patchesX(level), m_shardPatches);
}

std::int64_t PyramidLayout::shardsY(int level) const {
    return ceilDiv(patchesY(level), m_shardPatches);
}

bool PyramidLayout::contains(const PatchId& id) const {
    return id.level >= 0 && id.level <= m_finestLevel && id.x >= 0 && id.y >= 0 &&
           id.x < patchesX(id.level) && id.y < patchesY(id.level);
}

bool PyramidLayout::contains(const ShardId& s) const {
    return s.level >= 0 && s.level <= m_finestLevel && s.x >= 0 && s.y >= 0 &&
           s.x < shardsX(s.level) && s.y < shardsY(s.level);
}

ShardId PyramidLayout::shardOf(const PatchId& id) const {
    TERRAIN_ASSERT(contains(id), "patch outside the pyramid");
    return {id.level, id.x / m_shardPatches, id.y / m_shardPatches};
}

int PyramidLayout::shardCountX(const ShardId& s) const {
    TERRAIN_ASSERT(contains(s), "shard outside the pyramid");
    return static_cast<int>(
        std::min<std::int64_t>(m_shardPatches, patchesX(s.level) - shardFirstX(s)));
}

int PyramidLayout::shardCountY(const ShardId& s) const {
    TERRAIN_ASSERT(contains(s), "shard outside the pyramid");
    return static_cast<int>(
        std::min<std::int64_t>(m_shardPatches, patchesY(s.level) - shardFirstY(s)));
}

std::filesystem::path PyramidLayout::shardPath(const ShardId& s) const {
    return std::filesystem::path(fmt::format("L{}", s.level)) / std::to_string(s.y) /
           fmt::format("{}.exr", s.x);
}

std::int64_t PyramidLayout::patchCount(int level) const {
    return patchesX(level) * patchesY(level);
}

std::int64_t PyramidLayout::shardCount(int level) const { return shardsX(level) * shardsY(level); }

}  // namespace terrain::io
