// cache::ImageryTileCache: keyed by (imagery layer, patch), least recently used evicted
// within the byte budget, absent tiles cheap, a tile over the whole budget refused unmoved,
// storage of tiles that left handed back for reuse.
#include "terrain/cache/ImageryTileCache.h"

#include <gtest/gtest.h>

namespace terrain::cache {
namespace {

io::ImageryTile tile(const io::PatchId& id, bool present = true) {
    io::ImageryTile t;
    t.id = id;
    t.info.present = present;
    if (present) {
        t.rgba.assign(io::kImageryTileBytes, 7);
        t.mips.assign(io::kImageryMipChainBytes, 7);
    }
    return t;
}

TEST(ImageryTileCacheTest, EvictsTheLeastRecentlyUsedWithinTheBudget) {
    ImageryTileCache cache(2 * ImageryTileCache::kPresentTileBytes +
                           20 * ImageryTileCache::kEntryOverheadBytes);
    const io::PatchId a{1, 0, 0};
    const io::PatchId b{1, 1, 0};
    EXPECT_EQ(cache.insert(0, tile(a)), TileCacheInsertResult::Inserted);
    EXPECT_EQ(cache.insert(1, tile(a)), TileCacheInsertResult::Inserted);  // another layer
    EXPECT_EQ(cache.entryCount(), 2U);
    ASSERT_NE(cache.find({a, 0}), nullptr);  // (a, 1) is now the least recent
    EXPECT_EQ(cache.insert(0, tile(b)), TileCacheInsertResult::Inserted);
    EXPECT_FALSE(cache.contains({a, 1}));
    EXPECT_TRUE(cache.contains({a, 0}));
    EXPECT_TRUE(cache.contains({b, 0}));
    EXPECT_EQ(cache.counters().evictions, 1U);
    EXPECT_LE(cache.bytes(), cache.budgetBytes());
    // Its storage is handed back for the I/O thread to read into.
    const auto evicted = cache.takeEvicted();
    ASSERT_TRUE(evicted);
    EXPECT_GE(evicted->rgba.capacity(), io::kImageryTileBytes);

    // Absent tiles cost only their bookkeeping: many fit beside the two present ones.
    for (int x = 0; x < 20; ++x) cache.insert(0, tile({3, x, 0}, false));
    EXPECT_TRUE(cache.contains({a, 0}));
    EXPECT_TRUE(cache.contains({b, 0}));
    ASSERT_NE(cache.peek({{3, 5, 0}, 0}), nullptr);
    EXPECT_FALSE(cache.peek({{3, 5, 0}, 0})->info.present);
    EXPECT_EQ(cache.insert(0, tile(b)), TileCacheInsertResult::Replaced);
    EXPECT_TRUE(cache.erase({b, 0}));
    EXPECT_FALSE(cache.erase({b, 0}));
}

TEST(ImageryTileCacheTest, ATileIsChargedTheStorageItHolds) {
    io::ImageryTile absent = tile({2, 0, 0}, false);
    EXPECT_EQ(ImageryTileCache::tileBytes(absent), ImageryTileCache::kEntryOverheadBytes);
    absent.rgba.reserve(io::kImageryTileBytes);  // read into a recycled buffer
    absent.mips.reserve(io::kImageryMipChainBytes);
    EXPECT_EQ(ImageryTileCache::tileBytes(absent), ImageryTileCache::kPresentTileBytes);
}

TEST(ImageryTileCacheTest, ATileOverTheWholeBudgetIsRefusedUnmoved) {
    ImageryTileCache cache(ImageryTileCache::kPresentTileBytes - 1);
    io::ImageryTile t = tile({0, 0, 0});
    EXPECT_EQ(cache.insert(0, std::move(t)), TileCacheInsertResult::TooLarge);
    EXPECT_EQ(t.rgba.size(), io::kImageryTileBytes);  // NOLINT(bugprone-use-after-move)
    EXPECT_EQ(cache.entryCount(), 0U);
}

}  // namespace
}  // namespace terrain::cache
