// RecyclingLoadMap, the streamers' map of loads under way: an erased load's node is parked
// and reused, so after reserve() inserting and erasing loads allocates nothing; a present
// key keeps its value and does not make a fresh one.
#include "AllocationCounter.h"
#include "terrain/runtime/RecyclingLoadMap.h"

#include <gtest/gtest.h>

#include <cstddef>
#include <functional>
#include <iterator>

namespace terrain::runtime {
namespace {

using Map = RecyclingLoadMap<int, int, std::hash<int>>;

TEST(RecyclingLoadMapTest, FindOrInsertMakesAFreshValueOnlyForANewKey) {
    Map loads;
    int made = 0;
    loads.findOrInsert(7, [&] { return ++made * 10; });
    EXPECT_EQ(loads.findOrInsert(7, [&] { return ++made * 10; }), 10);
    EXPECT_EQ(made, 1);
    loads.findOrInsert(7, [] { return 0; }) = 3;
    EXPECT_EQ(loads.find(7)->second, 3);
    EXPECT_EQ(loads.size(), 1U);
}

TEST(RecyclingLoadMapTest, EraseReturnsTheNextLoadAndKeepsTheOthers) {
    Map loads;
    for (int key = 0; key < 10; ++key) loads.findOrInsert(key, [&] { return key; });
    for (auto it = loads.begin(); it != loads.end();)
        it = it->first % 2 == 0 ? loads.erase(it) : std::next(it);
    EXPECT_EQ(loads.size(), 5U);
    for (int key = 0; key < 10; ++key) EXPECT_EQ(loads.find(key) != loads.end(), key % 2 == 1);
}

TEST(RecyclingLoadMapTest, ReusedNodesMakeSteadyLoadsAllocateNothing) {
    constexpr int kLoads = 64;
    Map loads;
    loads.reserve(kLoads);
    // The first loads allocate their nodes; erased, the nodes are parked.
    for (int key = 0; key < kLoads; ++key) loads.findOrInsert(key, [] { return 0; });
    for (auto it = loads.begin(); it != loads.end();) it = loads.erase(it);
    const test::AllocationScope scope;
    for (int round = 1; round <= 3; ++round) {
        for (int key = 0; key < kLoads; ++key)
            loads.findOrInsert(round * kLoads + key, [&] { return round; });
        for (auto it = loads.begin(); it != loads.end();) it = loads.erase(it);
    }
    EXPECT_EQ(scope.allocations(), 0U);
    EXPECT_EQ(loads.size(), 0U);
}

}  // namespace
}  // namespace terrain::runtime
