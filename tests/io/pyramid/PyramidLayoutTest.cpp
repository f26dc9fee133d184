// The pyramid's addressing arithmetic (docs/pyramid-format.md): levels, patch and shard
// counts, shard membership and paths, checked against the spec's definitions on every
// small case and on the sizes that matter (SRTM 1201, 16385, a 1.3 M × 600 k planet grid).
#include "terrain/pyramid/PyramidLayout.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

namespace terrain::io {
namespace {

std::int64_t ceilDiv(std::int64_t a, std::int64_t b) { return (a + b - 1) / b; }

PyramidLayout make(std::int64_t w, std::int64_t h, int n = 129, int b = 16, int s = 16) {
    auto layout = PyramidLayout::create(w, h, n, b, s);
    EXPECT_TRUE(layout.ok()) << (layout.ok() ? "" : layout.error().message);
    return layout.value();
}

// Every property the spec states, for one layout.
void checkLayout(const PyramidLayout& p) {
    SCOPED_TRACE(::testing::Message() << p.rasterWidth() << " × " << p.rasterHeight() << ", N "
                                      << p.patchSamples() << ", S " << p.shardPatches());
    const int quads = p.patchSamples() - 1;
    const int L = p.finestLevel();
    const std::int64_t fx = std::max<std::int64_t>(1, ceilDiv(p.rasterWidth() - 1, quads));
    const std::int64_t fy = std::max<std::int64_t>(1, ceilDiv(p.rasterHeight() - 1, quads));
    ASSERT_EQ(p.patchesX(L), fx);
    ASSERT_EQ(p.patchesY(L), fy);
    // Smallest L with 2^L ≥ max(fx, fy).
    ASSERT_GE(std::int64_t{1} << L, std::max(fx, fy));
    if (L > 0) {
        ASSERT_LT(std::int64_t{1} << (L - 1), std::max(fx, fy));
    }
    ASSERT_EQ(p.levelCount(), L + 1);
    ASSERT_EQ(p.patchesX(0), 1);
    ASSERT_EQ(p.patchesY(0), 1);
    for (int l = L; l >= 0; --l) {
        ASSERT_EQ(p.levelStep(l), std::int64_t{1} << (L - l));
        if (l < L) {
            ASSERT_EQ(p.patchesX(l), ceilDiv(p.patchesX(l + 1), 2));
            ASSERT_EQ(p.patchesY(l), ceilDiv(p.patchesY(l + 1), 2));
        }
        ASSERT_LE(p.patchesX(l), std::int64_t{1} << l);
        // The level's patches cover the DEM, and the last one overlaps it.
        ASSERT_GE((p.levelSamplesX(l) - 1) * p.levelStep(l), p.rasterWidth() - 1);
        ASSERT_GE((p.levelSamplesY(l) - 1) * p.levelStep(l), p.rasterHeight() - 1);
        ASSERT_LT((p.patchesX(l) - 1) * quads * p.levelStep(l), p.rasterWidth() - 1);
        ASSERT_LT((p.patchesY(l) - 1) * quads * p.levelStep(l), p.rasterHeight() - 1);
        ASSERT_EQ(p.patchCount(l), p.patchesX(l) * p.patchesY(l));
        ASSERT_EQ(p.shardsX(l), ceilDiv(p.patchesX(l), p.shardPatches()));
        ASSERT_EQ(p.shardsY(l), ceilDiv(p.patchesY(l), p.shardPatches()));
        ASSERT_EQ(p.shardCount(l), p.shardsX(l) * p.shardsY(l));
    }
}

// Every patch of a level lies in exactly one shard, whose ranges partition the level.
void checkShards(const PyramidLayout& p) {
    for (int l = 0; l <= p.finestLevel(); ++l) {
        std::int64_t covered = 0;
        for (std::int64_t sy = 0; sy < p.shardsY(l); ++sy)
            for (std::int64_t sx = 0; sx < p.shardsX(l); ++sx) {
                const ShardId s{l, sx, sy};
                ASSERT_TRUE(p.contains(s));
                const int cx = p.shardCountX(s), cy = p.shardCountY(s);
                ASSERT_GE(cx, 1);
                ASSERT_LE(cx, p.shardPatches());
                ASSERT_GE(cy, 1);
                ASSERT_LE(cy, p.shardPatches());
                covered += std::int64_t{cx} * cy;
                for (int ty = 0; ty < cy; ++ty)
                    for (int tx = 0; tx < cx; ++tx) {
                        const PatchId id{l, p.shardFirstX(s) + tx, p.shardFirstY(s) + ty};
                        ASSERT_TRUE(p.contains(id));
                        ASSERT_EQ(p.shardOf(id), s);
                    }
            }
        ASSERT_EQ(covered, p.patchCount(l));
        ASSERT_FALSE(p.contains(ShardId{l, p.shardsX(l), 0}));
        ASSERT_FALSE(p.contains(ShardId{l, 0, p.shardsY(l)}));
        ASSERT_FALSE(p.contains(PatchId{l, p.patchesX(l), 0}));
        ASSERT_FALSE(p.contains(PatchId{l, 0, p.patchesY(l)}));
        ASSERT_FALSE(p.contains(PatchId{l, -1, 0}));
    }
    ASSERT_FALSE(p.contains(PatchId{p.finestLevel() + 1, 0, 0}));
    ASSERT_FALSE(p.contains(PatchId{-1, 0, 0}));
}

TEST(PyramidLayout, SinglePatch) {
    for (std::int64_t side : {2, 3, 64, 128, 129}) {
        const PyramidLayout p = make(side, side);
        EXPECT_EQ(p.finestLevel(), 0);
        EXPECT_EQ(p.patchesX(0), 1);
        EXPECT_EQ(p.shardsX(0), 1);
        EXPECT_EQ(p.levelSamplesX(0), 129);
        checkLayout(p);
        checkShards(p);
    }
}

TEST(PyramidLayout, TwoByOnePatches) {
    const PyramidLayout p = make(130, 129);  // one sample past a patch: a second column
    EXPECT_EQ(p.finestLevel(), 1);
    EXPECT_EQ(p.patchesX(1), 2);
    EXPECT_EQ(p.patchesY(1), 1);
    EXPECT_EQ(p.patchesX(0), 1);
    EXPECT_EQ(p.levelStep(0), 2);
    checkLayout(p);
    checkShards(p);
}

TEST(PyramidLayout, Srtm1201) {
    const PyramidLayout p = make(1201, 1201);
    EXPECT_EQ(p.finestLevel(), 4);
    const std::vector<std::int64_t> expected = {1, 2, 3, 5, 10};
    for (int l = 0; l <= 4; ++l) EXPECT_EQ(p.patchesX(l), expected[static_cast<std::size_t>(l)]);
    EXPECT_EQ(p.shardsX(4), 1);
    EXPECT_EQ(p.levelStep(0), 16);
    checkLayout(p);
    checkShards(p);
}

TEST(PyramidLayout, PowerOfTwoPlusOne16385) {
    const PyramidLayout p = make(16385, 16385);
    EXPECT_EQ(p.finestLevel(), 7);
    std::int64_t patches = 0;
    for (int l = 0; l <= 7; ++l) {
        EXPECT_EQ(p.patchesX(l), std::int64_t{1} << l);
        patches += p.patchCount(l);
    }
    EXPECT_EQ(patches, 21845);  // (4^8 − 1) / 3
    EXPECT_EQ(p.shardsX(7), 8);
    EXPECT_EQ(p.shardCountX(ShardId{7, 7, 7}), 16);
    EXPECT_EQ(p.shardCountX(ShardId{3, 0, 0}), 8);
    checkLayout(p);
    checkShards(p);
}

TEST(PyramidLayout, PlanetGrid) {
    const PyramidLayout p = make(1'300'000, 600'000);
    EXPECT_EQ(p.patchesX(p.finestLevel()), 10157);  // ceil(1,299,999 / 128)
    EXPECT_EQ(p.patchesY(p.finestLevel()), 4688);   // ceil(599,999 / 128)
    EXPECT_EQ(p.finestLevel(), 14);                 // 2^14 = 16384 ≥ 10157 > 8192
    EXPECT_EQ(p.shardsX(14), 635);
    EXPECT_EQ(p.shardsY(14), 293);
    EXPECT_EQ(p.shardCountX(ShardId{14, 634, 0}), 10157 - 634 * 16);
    EXPECT_EQ(p.shardCountY(ShardId{14, 0, 292}), 4688 - 292 * 16);
    checkLayout(p);
    const PatchId last{14, 10156, 4687};
    EXPECT_TRUE(p.contains(last));
    EXPECT_EQ(p.shardOf(last), (ShardId{14, 634, 292}));
    EXPECT_EQ(p.shardPath(p.shardOf(last)).generic_string(), "L14/292/634.exr");
}

TEST(PyramidLayout, ExhaustiveSmallRasters) {
    for (int n : {5, 9, 17}) {
        for (int s : {1, 2, 3}) {
            for (std::int64_t w = 2; w <= 160; ++w) {
                for (std::int64_t h : {2, 3, 5, 9, 16, 17, 18, 33, 65, 100, 160}) {
                    const PyramidLayout p = make(w, h, n, 4, s);
                    checkLayout(p);
                    if (HasFatalFailure()) return;
                }
            }
            for (std::int64_t w : {2, 7, 40, 129}) {
                for (std::int64_t h = 2; h <= 100; ++h) {
                    const PyramidLayout p = make(w, h, n, 4, s);
                    checkLayout(p);
                    checkShards(p);
                    if (HasFatalFailure()) return;
                }
            }
        }
    }
}

TEST(PyramidLayout, DerivedSizes) {
    const PyramidLayout p = make(1201, 1201);
    EXPECT_EQ(p.patchSamples(), 129);
    EXPECT_EQ(p.patchQuads(), 128);
    EXPECT_EQ(p.tileSamples(), 131);
    EXPECT_EQ(p.apronSamples(), 1);
    EXPECT_EQ(p.blocksPerSide(), 8);
    EXPECT_EQ(p.levelSamplesX(4), 10 * 128 + 1);
    EXPECT_EQ(p.patchOriginX(PatchId{4, 3, 2}), 384);
    EXPECT_EQ(p.patchOriginY(PatchId{4, 3, 2}), 256);
    EXPECT_EQ(p.shardPath(ShardId{3, 5, 7}).generic_string(), "L3/7/5.exr");
    EXPECT_EQ(p, make(1201, 1201));
    EXPECT_NE(p, make(1201, 1202));
}

void expectError(std::int64_t w, std::int64_t h, int n, int b, int s, const std::string& needle) {
    const auto layout = PyramidLayout::create(w, h, n, b, s);
    ASSERT_FALSE(layout.ok()) << w << " × " << h << " N " << n << " B " << b << " S " << s;
    EXPECT_NE(layout.error().message.find(needle), std::string::npos) << layout.error().message;
}

TEST(PyramidLayout, RejectsBadParameters) {
    expectError(1, 100, 129, 16, 16, "at least 2 × 2");
    expectError(100, 0, 129, 16, 16, "at least 2 × 2");
    expectError(PyramidLayout::kMaxRasterSamples + 1, 10, 129, 16, 16, "samples a side");
    for (int n : {-1, 0, 1, 2, 3, 4, 128, 130, 32769})
        expectError(1201, 1201, n, 1, 16, "patch size");
    expectError(1201, 1201, 129, 0, 16, "tessellation block");
    expectError(1201, 1201, 129, 3, 16, "tessellation block");
    expectError(1201, 1201, 129, 256, 16, "tessellation block");
    // GL clamps a tessellation factor to 64: a block of 128 quads would skip samples.
    expectError(1201, 1201, 129, 128, 16, "GL's largest tessellation factor");
    expectError(1201, 1201, 16385, 128, 16, "tessellation block");
    EXPECT_TRUE(PyramidLayout::create(1201, 1201, 129, 64, 16).ok());
    expectError(1201, 1201, 129, 16, 0, "shard of 0");
    expectError(1201, 1201, 129, 16, -3, "shard of -3");
    expectError(1201, 1201, 129, 16, PyramidLayout::kMaxShardPatches + 1, "shard of");
    expectError(PyramidLayout::kMaxRasterSamples, 10, 5, 4, 1, "2^31 shards");
    EXPECT_TRUE(PyramidLayout::create(2, 2, 5, 4, 1).ok());
    EXPECT_TRUE(PyramidLayout::create(3, 3, 5, 1, 1).ok());
    EXPECT_TRUE(PyramidLayout::create(2, 2, 16385, 16, 1).ok());
}

}  // namespace
}  // namespace terrain::io
