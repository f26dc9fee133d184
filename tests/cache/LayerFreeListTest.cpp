// LayerFreeList: exhaustion, reuse, programmer-error asserts and a randomized comparison
// with a std::set model, checking the invariants after every step.
#include "terrain/cache/LayerFreeList.h"

#include <gtest/gtest.h>

#include <random>
#include <set>
#include <vector>

namespace terrain::cache {
namespace {

void expectValid(const LayerFreeList& list) {
    const auto maybeViolation = list.checkInvariants();
    EXPECT_FALSE(maybeViolation.has_value()) << *maybeViolation;
}

TEST(LayerFreeList, AllocatesEveryLayerOnceThenNothing) {
    LayerFreeList list(8);
    EXPECT_EQ(list.capacity(), 8);
    EXPECT_EQ(list.freeCount(), 8);
    EXPECT_EQ(list.usedCount(), 0);
    std::set<int> seen;
    for (int i = 0; i < 8; ++i) {
        const auto layer = list.allocate();
        ASSERT_TRUE(layer.has_value());
        EXPECT_EQ(*layer, i) << "layers are handed out from 0 upwards";
        EXPECT_TRUE(list.isAllocated(*layer));
        seen.insert(*layer);
        expectValid(list);
    }
    EXPECT_EQ(seen.size(), 8u);
    EXPECT_EQ(list.freeCount(), 0);
    EXPECT_EQ(list.usedCount(), 8);
    EXPECT_FALSE(list.allocate().has_value());
    EXPECT_EQ(list.usedCount(), 8);
    expectValid(list);
}

TEST(LayerFreeList, ReleasedLayerIsReallocated) {
    LayerFreeList list(4);
    for (int i = 0; i < 4; ++i) {
        ASSERT_TRUE(list.allocate().has_value());
    }
    list.release(2);
    EXPECT_FALSE(list.isAllocated(2));
    EXPECT_EQ(list.freeCount(), 1);
    EXPECT_EQ(list.usedCount(), 3);
    expectValid(list);
    EXPECT_EQ(list.allocate(), std::optional<int>(2));
    EXPECT_FALSE(list.allocate().has_value());
    list.release(0);
    list.release(3);
    EXPECT_EQ(list.allocate(), std::optional<int>(3)) << "last released, first reused";
    EXPECT_EQ(list.allocate(), std::optional<int>(0));
    expectValid(list);
}

TEST(LayerFreeList, ZeroCapacityHasNothingToGive) {
    LayerFreeList list(0);
    EXPECT_FALSE(list.allocate().has_value());
    EXPECT_EQ(list.freeCount(), 0);
    EXPECT_EQ(list.usedCount(), 0);
    expectValid(list);
}

TEST(LayerFreeListDeathTest, ReleasingAFreeLayerAsserts) {
    LayerFreeList list(4);
    EXPECT_DEATH(list.release(1), "already free");
    const auto layer = list.allocate();
    ASSERT_TRUE(layer.has_value());
    list.release(*layer);
    EXPECT_DEATH(list.release(*layer), "already free");
}

TEST(LayerFreeListDeathTest, OutOfRangeLayersAssert) {
    LayerFreeList list(4);
    EXPECT_DEATH(list.release(4), "out of range");
    EXPECT_DEATH(list.release(-1), "out of range");
    EXPECT_DEATH((void)list.isAllocated(4), "out of range");
}

TEST(LayerFreeList, RandomizedAgainstSetModel) {
    constexpr int kCapacity = 64;
    constexpr int kOperations = 100'000;
    LayerFreeList list(kCapacity);
    std::set<int> used;          // the model
    std::vector<int> usedOrder;  // the same layers, for picking one at random
    std::mt19937 rng(12345);
    std::uniform_int_distribution<int> op(0, 99);
    std::uniform_int_distribution<int> anyLayer(0, kCapacity - 1);
    for (int step = 0; step < kOperations; ++step) {
        const int choice = op(rng);
        if (choice < 50) {  // slightly more allocations than releases: often full
            const auto layer = list.allocate();
            if (used.size() == kCapacity) {
                ASSERT_FALSE(layer.has_value()) << "step " << step;
            } else {
                ASSERT_TRUE(layer.has_value()) << "step " << step;
                ASSERT_GE(*layer, 0);
                ASSERT_LT(*layer, kCapacity);
                ASSERT_TRUE(used.insert(*layer).second) << "layer handed out twice, step " << step;
                usedOrder.push_back(*layer);
            }
        } else if (choice < 95) {
            if (!usedOrder.empty()) {
                std::uniform_int_distribution<std::size_t> pick(0, usedOrder.size() - 1);
                const std::size_t index = pick(rng);
                const int layer = usedOrder[index];
                usedOrder[index] = usedOrder.back();
                usedOrder.pop_back();
                used.erase(layer);
                list.release(layer);
            }
        } else {
            const int layer = anyLayer(rng);
            ASSERT_EQ(list.isAllocated(layer), used.contains(layer)) << "step " << step;
        }
        ASSERT_EQ(list.usedCount(), static_cast<int>(used.size())) << "step " << step;
        ASSERT_EQ(list.freeCount(), kCapacity - static_cast<int>(used.size()));
        const auto maybeViolation = list.checkInvariants();
        ASSERT_FALSE(maybeViolation.has_value()) << "step " << step << ": " << *maybeViolation;
    }
    for (int layer = 0; layer < kCapacity; ++layer) {
        EXPECT_EQ(list.isAllocated(layer), used.contains(layer));
    }
}

}  // namespace
}  // namespace terrain::cache
