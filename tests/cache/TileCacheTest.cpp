// TileCache: LRU order, exact counters, budget changes, oversized records, erase, recycling,
// no allocation once warm, the PatchId hash, and a randomized comparison with a std::list
// LRU model.
#include "terrain/cache/TileCache.h"

#include "terrain/pyramid/PatchIdHash.h"

#include "AllocationCounter.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <list>
#include <random>
#include <unordered_set>
#include <vector>

namespace terrain::cache {
namespace {

io::PatchRecord makeRecord(io::PatchId id, std::size_t heightCount) {
    io::PatchRecord record;
    record.id = id;
    record.heights.assign(heightCount, float(id.x));
    return record;
}

io::PatchId patch(std::int64_t x) { return io::PatchId{0, x, 0}; }

// Bytes charged for a record of makeRecord(·, heightCount).
std::size_t chargedBytes(std::size_t heightCount) {
    return heightCount * sizeof(float) + TileCache::kEntryOverheadBytes;
}

constexpr std::size_t kHeights = 100;

TEST(TileCache, RecordBytesCountsEveryVectorPlusOverhead) {
    io::PatchRecord record = makeRecord(patch(0), 10);
    record.valid.assign(7, 1);
    record.blockErrors.resize(3);
    EXPECT_EQ(TileCache::recordBytes(record), 10 * sizeof(float) + 7 + 3 * sizeof(io::BlockErrors) +
                                                  TileCache::kEntryOverheadBytes);
}

TEST(TileCache, TileBytesIsWhatAWholeTileOfTheLayoutIsCharged) {
    const io::PyramidLayout layout = io::PyramidLayout::create(513, 513, 33, 8, 4).value();
    for (const bool withMask : {false, true}) {
        io::PatchRecord record;
        const auto tile = static_cast<std::size_t>(layout.tileSamples());
        const auto blocks = static_cast<std::size_t>(layout.blocksPerSide());
        record.heights.resize(tile * tile);
        if (withMask) record.valid.resize(tile * tile);
        record.blockErrors.resize(blocks * blocks);
        EXPECT_EQ(TileCache::tileBytes(layout, withMask), TileCache::recordBytes(record));
        TileCache tooSmall(TileCache::recordBytes(record) - 1);
        EXPECT_EQ(tooSmall.insert(std::move(record)), TileCacheInsertResult::TooLarge);
    }
}

TEST(TileCache, FindReturnsTheStoredRecordAndCounts) {
    TileCache cache(10 * chargedBytes(kHeights));
    EXPECT_EQ(cache.insert(makeRecord(patch(1), kHeights)), TileCacheInsertResult::Inserted);
    EXPECT_EQ(cache.bytes(), chargedBytes(kHeights));
    const io::PatchRecord* found = cache.find(patch(1));
    ASSERT_NE(found, nullptr);
    EXPECT_EQ(found->id, patch(1));
    EXPECT_EQ(found->heights.size(), kHeights);
    EXPECT_EQ(cache.find(patch(2)), nullptr);
    EXPECT_EQ(cache.find(patch(2)), nullptr);
    EXPECT_EQ(cache.counters(), (TileCacheCounters{1, 2, 0, 1}));
    cache.resetCounters();
    EXPECT_EQ(cache.counters(), TileCacheCounters{});
    EXPECT_TRUE(cache.contains(patch(1)));  // resetting counters keeps the entries
}

TEST(TileCache, EvictsLeastRecentlyUsedAndTouchingProtects) {
    TileCache cache(3 * chargedBytes(kHeights));
    for (int x = 0; x < 3; ++x) {
        cache.insert(makeRecord(patch(x), kHeights));
    }
    ASSERT_NE(cache.find(patch(0)), nullptr);  // 0 becomes most recent: 1 is now oldest
    cache.insert(makeRecord(patch(3), kHeights));
    EXPECT_TRUE(cache.contains(patch(0)));
    EXPECT_FALSE(cache.contains(patch(1)));
    EXPECT_TRUE(cache.contains(patch(2)));
    EXPECT_TRUE(cache.contains(patch(3)));
    EXPECT_EQ(cache.idsLeastRecentFirst(), (std::vector{patch(2), patch(0), patch(3)}));
    EXPECT_EQ(cache.counters(), (TileCacheCounters{1, 0, 1, 4}));
    EXPECT_LE(cache.bytes(), cache.budgetBytes());
}

TEST(TileCache, ContainsDoesNotChangeLruOrderOrCounters) {
    TileCache cache(3 * chargedBytes(kHeights));
    for (int x = 0; x < 3; ++x) {
        cache.insert(makeRecord(patch(x), kHeights));
    }
    EXPECT_TRUE(cache.contains(patch(0)));
    EXPECT_FALSE(cache.contains(patch(9)));
    EXPECT_EQ(cache.counters(), (TileCacheCounters{0, 0, 0, 3}));
    cache.insert(makeRecord(patch(3), kHeights));
    EXPECT_FALSE(cache.contains(patch(0))) << "contains() must not protect an entry";
}

TEST(TileCache, PeekReturnsTheRecordButDoesNotChangeLruOrderOrCounters) {
    TileCache cache(3 * chargedBytes(kHeights));
    for (int x = 0; x < 3; ++x) {
        cache.insert(makeRecord(patch(x), kHeights));
    }
    const io::PatchRecord* peeked = cache.peek(patch(0));
    ASSERT_NE(peeked, nullptr);
    EXPECT_EQ(peeked->id, patch(0));
    EXPECT_EQ(cache.peek(patch(9)), nullptr);
    EXPECT_EQ(cache.counters(), (TileCacheCounters{0, 0, 0, 3}));
    cache.insert(makeRecord(patch(3), kHeights));
    EXPECT_EQ(cache.peek(patch(0)), nullptr) << "peek() must not protect an entry";
}

TEST(TileCache, LargerRecordEvictsSeveral) {
    TileCache cache(4 * chargedBytes(kHeights));
    for (int x = 0; x < 4; ++x) {
        cache.insert(makeRecord(patch(x), kHeights));
    }
    // Needs the room of three small entries (overhead included).
    cache.insert(makeRecord(patch(9), 3 * kHeights + 2 * TileCache::kEntryOverheadBytes / 4));
    EXPECT_EQ(cache.idsLeastRecentFirst(), (std::vector{patch(3), patch(9)}));
    EXPECT_EQ(cache.counters().evictions, 3u);
    EXPECT_LE(cache.bytes(), cache.budgetBytes());
}

TEST(TileCache, LoweringTheBudgetEvictsOldestFirst) {
    TileCache cache(5 * chargedBytes(kHeights));
    for (int x = 0; x < 5; ++x) {
        cache.insert(makeRecord(patch(x), kHeights));
    }
    ASSERT_NE(cache.find(patch(0)), nullptr);
    cache.setBudgetBytes(2 * chargedBytes(kHeights));
    EXPECT_EQ(cache.budgetBytes(), 2 * chargedBytes(kHeights));
    EXPECT_EQ(cache.idsLeastRecentFirst(), (std::vector{patch(4), patch(0)}));
    EXPECT_EQ(cache.bytes(), 2 * chargedBytes(kHeights));
    EXPECT_EQ(cache.counters().evictions, 3u);
    cache.setBudgetBytes(0);
    EXPECT_EQ(cache.entryCount(), 0u);
    EXPECT_EQ(cache.bytes(), 0u);
    EXPECT_EQ(cache.counters().evictions, 5u);
    cache.setBudgetBytes(10 * chargedBytes(kHeights));  // raising evicts nothing
    EXPECT_EQ(cache.counters().evictions, 5u);
}

TEST(TileCache, OversizedRecordIsRejectedAndLeavesTheCacheAlone) {
    TileCache cache(3 * chargedBytes(kHeights));
    cache.insert(makeRecord(patch(0), kHeights));
    cache.insert(makeRecord(patch(1), kHeights));
    io::PatchRecord huge = makeRecord(patch(2), 3 * kHeights + 1000);
    ASSERT_GT(TileCache::recordBytes(huge), cache.budgetBytes());
    EXPECT_EQ(cache.insert(std::move(huge)), TileCacheInsertResult::TooLarge);
    EXPECT_EQ(huge.heights.size(), 3 * kHeights + 1000) << "rejected record is not moved from";
    EXPECT_FALSE(cache.contains(patch(2)));
    EXPECT_EQ(cache.entryCount(), 2u);
    EXPECT_EQ(cache.bytes(), 2 * chargedBytes(kHeights));
    EXPECT_EQ(cache.counters(), (TileCacheCounters{0, 0, 0, 2}));
    // Exactly the budget fits.
    TileCache exact(chargedBytes(kHeights));
    EXPECT_EQ(exact.insert(makeRecord(patch(0), kHeights)), TileCacheInsertResult::Inserted);
    EXPECT_EQ(exact.bytes(), exact.budgetBytes());
}

TEST(TileCache, EraseRemovesWithoutCountingAnEviction) {
    TileCache cache(3 * chargedBytes(kHeights));
    cache.insert(makeRecord(patch(0), kHeights));
    cache.insert(makeRecord(patch(1), kHeights));
    EXPECT_TRUE(cache.erase(patch(0)));
    EXPECT_FALSE(cache.erase(patch(0)));
    EXPECT_FALSE(cache.contains(patch(0)));
    EXPECT_EQ(cache.find(patch(0)), nullptr);
    EXPECT_EQ(cache.bytes(), chargedBytes(kHeights));
    EXPECT_EQ(cache.counters(), (TileCacheCounters{0, 1, 0, 2}));
}

TEST(TileCache, InsertingAnExistingIdReplacesIt) {
    TileCache cache(3 * chargedBytes(kHeights));
    cache.insert(makeRecord(patch(0), kHeights));
    cache.insert(makeRecord(patch(1), kHeights));
    EXPECT_EQ(cache.insert(makeRecord(patch(0), 2 * kHeights)), TileCacheInsertResult::Replaced);
    EXPECT_EQ(cache.entryCount(), 2u);
    EXPECT_EQ(cache.bytes(), chargedBytes(kHeights) + chargedBytes(2 * kHeights));
    EXPECT_EQ(cache.idsLeastRecentFirst(), (std::vector{patch(1), patch(0)}));
    EXPECT_EQ(cache.find(patch(0))->heights.size(), 2 * kHeights);
    EXPECT_EQ(cache.counters().evictions, 0u);
}

TEST(TileCache, LeavingRecordsAreKeptForReuseUpToALimit) {
    TileCache cache(chargedBytes(kHeights));
    EXPECT_FALSE(cache.takeEvicted().has_value());
    for (int x = 0; x < 10; ++x) {
        cache.insert(makeRecord(patch(x), kHeights));
    }
    EXPECT_EQ(cache.counters().evictions, 9u);
    EXPECT_EQ(cache.recycledCount(), TileCache::kMaxRecycledRecords);
    EXPECT_EQ(cache.bytes(), chargedBytes(kHeights)) << "recycled records are not charged";
    for (std::size_t i = 0; i < TileCache::kMaxRecycledRecords; ++i) {
        const auto maybeRecord = cache.takeEvicted();
        ASSERT_TRUE(maybeRecord.has_value());
        EXPECT_EQ(maybeRecord->heights.size(), kHeights);
        EXPECT_GE(maybeRecord->heights.capacity(), kHeights) << "storage survives for reuse";
    }
    EXPECT_FALSE(cache.takeEvicted().has_value());
    cache.erase(patch(9));
    EXPECT_EQ(cache.recycledCount(), 1u);
}

// Records for one round of churn, made up front: the vectors a record brings are the
// caller's allocations, not the cache's. Ids from a window of 48 patches, so inserts
// replace and finds miss; three sizes, so one insert may evict several entries; now and
// then one larger than the whole budget.
std::vector<io::PatchRecord> churnRecords(std::mt19937& rng, std::size_t count,
                                          std::size_t budgetBytes) {
    const std::size_t sizes[] = {kHeights / 2, kHeights, 2 * kHeights, budgetBytes / sizeof(float)};
    std::vector<io::PatchRecord> records;
    records.reserve(count);
    for (std::size_t i = 0; i < count; ++i) {
        const std::size_t size = rng() % 50 == 0 ? sizes[3] : sizes[rng() % 3];
        records.push_back(makeRecord(patch(static_cast<std::int64_t>(rng() % 48)), size));
    }
    return records;
}

// A streaming loop's use of the cache: inserts (evicting, replacing, rejecting), hits and
// misses, erases, evicted records decoded into again (takeEvicted, then insert), and
// budget squeezes. Consumes `records`.
void churn(TileCache& cache, std::vector<io::PatchRecord>& records, std::mt19937& rng) {
    const std::size_t budgetBytes = cache.budgetBytes();
    std::size_t next = 0;
    for (int step = 0; step < 3000; ++step) {
        const io::PatchId id = patch(static_cast<std::int64_t>(rng() % 48));
        const auto op = rng() % 10;
        if (op < 4) {
            if (next < records.size()) cache.insert(std::move(records[next++]));
        } else if (op < 7) {
            cache.find(id);
        } else if (op < 8) {
            cache.erase(id);
        } else if (op < 9) {
            if (auto maybeRecord = cache.takeEvicted()) {
                maybeRecord->id = id;
                cache.insert(std::move(*maybeRecord));
            }
        } else if (step % 100 == 0) {
            cache.setBudgetBytes(budgetBytes / 2);
            cache.setBudgetBytes(budgetBytes);
        }
    }
}

TEST(TileCache, AllocatesNothingOnceWarm) {
    const std::size_t budgetBytes = 16 * chargedBytes(kHeights);
    TileCache cache(budgetBytes);
    std::mt19937 rng(7);
    std::vector<io::PatchRecord> records = churnRecords(rng, 1500, budgetBytes);
    {
        const test::AllocationScope warmUp;
        // The high-water entry count: as many of the smallest records as the budget holds.
        for (std::int64_t x = 100; cache.bytes() + chargedBytes(kHeights / 2) <= budgetBytes; ++x) {
            cache.insert(makeRecord(patch(x), kHeights / 2));
        }
        churn(cache, records, rng);
        EXPECT_GT(warmUp.allocations(), 0u) << "the counter must see the cache's nodes";
    }

    records = churnRecords(rng, 1500, budgetBytes);
    const TileCacheCounters before = cache.counters();
    std::uint64_t allocations = 0;
    {
        const test::AllocationScope scope;
        churn(cache, records, rng);
        allocations = scope.allocations();
    }
    EXPECT_EQ(allocations, 0u);
    // The round did exercise every path.
    const TileCacheCounters& after = cache.counters();
    EXPECT_GT(after.insertions - before.insertions, 500u);
    EXPECT_GT(after.evictions - before.evictions, 200u);
    EXPECT_GT(after.hits - before.hits, 200u);
    EXPECT_GT(after.misses - before.misses, 200u);
    EXPECT_LE(cache.bytes(), cache.budgetBytes());
}

TEST(PatchIdHash, NoCollisionsOverTypicalRanges) {
    io::PatchIdHash hash;
    std::unordered_set<std::size_t> seen;
    std::size_t count = 0;
    for (int level = 0; level < 24; ++level) {
        const std::int64_t side = std::min<std::int64_t>(std::int64_t{1} << level, 48);
        for (std::int64_t y = 0; y < side; ++y) {
            for (std::int64_t x = 0; x < side; ++x) {
                seen.insert(hash(io::PatchId{level, x, y}));
                ++count;
            }
        }
    }
    // Far corners of a deep level, and swapped coordinates.
    for (std::int64_t d = 0; d < 64; ++d) {
        const std::int64_t far = (std::int64_t{1} << 28) - 1 - d;
        seen.insert(hash(io::PatchId{30, far, d}));
        seen.insert(hash(io::PatchId{30, d, far}));
        count += 2;
    }
    EXPECT_EQ(seen.size(), count);
    EXPECT_NE(hash(io::PatchId{0, 1, 2}), hash(io::PatchId{0, 2, 1}));
    EXPECT_NE(hash(io::PatchId{1, 0, 0}), hash(io::PatchId{0, 0, 0}));
    EXPECT_NE(hash(io::PatchId{0, std::int64_t{1} << 29, 0}), hash(io::PatchId{0, 0, 0}));
}

// The reference: a std::list in LRU order (front = most recent) with linear searches.
struct ModelEntry {
    io::PatchId id;
    std::size_t bytes;
};

class LruModel {
public:
    explicit LruModel(std::size_t budgetBytes) : m_budgetBytes(budgetBytes) {}

    TileCacheInsertResult insert(io::PatchId id, std::size_t bytes) {
        if (bytes > m_budgetBytes) {
            return TileCacheInsertResult::TooLarge;
        }
        const bool replaced = erase(id);
        while (total() + bytes > m_budgetBytes) {
            m_entries.pop_back();
            ++counters.evictions;
        }
        m_entries.push_front({id, bytes});
        ++counters.insertions;
        return replaced ? TileCacheInsertResult::Replaced : TileCacheInsertResult::Inserted;
    }
    bool find(io::PatchId id) {
        const auto it = locate(id);
        if (it == m_entries.end()) {
            ++counters.misses;
            return false;
        }
        ++counters.hits;
        m_entries.splice(m_entries.begin(), m_entries, it);
        return true;
    }
    bool contains(io::PatchId id) { return locate(id) != m_entries.end(); }
    bool erase(io::PatchId id) {
        const auto it = locate(id);
        if (it == m_entries.end()) {
            return false;
        }
        m_entries.erase(it);
        return true;
    }
    void setBudgetBytes(std::size_t budgetBytes) {
        m_budgetBytes = budgetBytes;
        while (total() > m_budgetBytes) {
            m_entries.pop_back();
            ++counters.evictions;
        }
    }
    std::size_t total() const {
        std::size_t sum = 0;
        for (const auto& e : m_entries) sum += e.bytes;
        return sum;
    }
    std::vector<io::PatchId> idsLeastRecentFirst() const {
        std::vector<io::PatchId> ids;
        for (auto it = m_entries.rbegin(); it != m_entries.rend(); ++it) ids.push_back(it->id);
        return ids;
    }

    TileCacheCounters counters;

private:
    std::list<ModelEntry>::iterator locate(io::PatchId id) {
        return std::find_if(m_entries.begin(), m_entries.end(),
                            [&](const ModelEntry& e) { return e.id == id; });
    }
    std::size_t m_budgetBytes;
    std::list<ModelEntry> m_entries;
};

TEST(TileCache, RandomizedAgainstListModel) {
    std::mt19937 rng(2024);
    const std::size_t initialBudget = 20 * chargedBytes(kHeights);
    TileCache cache(initialBudget);
    LruModel model(initialBudget);
    std::uniform_int_distribution<int> op(0, 99);
    std::uniform_int_distribution<int> level(0, 3);
    std::uniform_int_distribution<std::int64_t> coord(0, 5);
    std::uniform_int_distribution<std::size_t> heights(0, 4 * kHeights);
    std::uniform_int_distribution<std::size_t> budget(0, 40 * chargedBytes(kHeights));
    for (int step = 0; step < 20'000; ++step) {
        const io::PatchId id{level(rng), coord(rng), coord(rng)};
        const int choice = op(rng);
        if (choice < 40) {
            const std::size_t count = heights(rng);
            ASSERT_EQ(cache.insert(makeRecord(id, count)), model.insert(id, chargedBytes(count)))
                << "step " << step;
        } else if (choice < 80) {
            const io::PatchRecord* found = cache.find(id);
            ASSERT_EQ(found != nullptr, model.find(id)) << "step " << step;
            if (found != nullptr) {
                ASSERT_EQ(found->id, id);
            }
        } else if (choice < 90) {
            ASSERT_EQ(cache.contains(id), model.contains(id)) << "step " << step;
        } else if (choice < 98) {
            ASSERT_EQ(cache.erase(id), model.erase(id)) << "step " << step;
        } else {
            const std::size_t newBudget = budget(rng);
            cache.setBudgetBytes(newBudget);
            model.setBudgetBytes(newBudget);
        }
        ASSERT_LE(cache.bytes(), cache.budgetBytes()) << "step " << step;
        ASSERT_EQ(cache.bytes(), model.total()) << "step " << step;
        ASSERT_EQ(cache.counters(), model.counters) << "step " << step;
        ASSERT_EQ(cache.idsLeastRecentFirst(), model.idsLeastRecentFirst()) << "step " << step;
        ASSERT_EQ(cache.entryCount(), cache.idsLeastRecentFirst().size());
        if (step % 1000 == 999) {
            while (cache.takeEvicted().has_value()) {
            }
        }
    }
    EXPECT_GT(cache.counters().evictions, 100u) << "the test should exercise eviction";
    EXPECT_GT(cache.counters().hits, 100u);
}

}  // namespace
}  // namespace terrain::cache
