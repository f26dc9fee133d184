// cache::LayerLru: least-recently-used order of GPU pool layers, O(1) operations.
#include "terrain/cache/LayerLru.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

namespace terrain::cache {
namespace {

TEST(LayerLru, EmptyHasNoLeastRecent) {
    const LayerLru lru(4);
    EXPECT_EQ(lru.size(), 0);
    EXPECT_EQ(lru.leastRecent(), std::nullopt);
    EXPECT_FALSE(lru.contains(3));
}

TEST(LayerLru, TouchMovesALayerToTheRecentEnd) {
    LayerLru lru(4);
    lru.insert(2, 1);
    lru.insert(0, 1);
    lru.insert(3, 2);
    EXPECT_EQ(lru.leastRecent(), 2);
    lru.touch(2, 3);
    EXPECT_EQ(lru.leastRecent(), 0);
    EXPECT_EQ(lru.lastUsedFrame(2), 3u);
    lru.remove(0);
    EXPECT_EQ(lru.leastRecent(), 3);
    lru.remove(3);
    lru.remove(2);
    EXPECT_EQ(lru.leastRecent(), std::nullopt);
    EXPECT_EQ(lru.size(), 0);
}

// Against a plain vector model: the same order after thousands of random operations.
TEST(LayerLru, MatchesAModelUnderRandomOperations) {
    constexpr int kLayers = 16;
    LayerLru lru(kLayers);
    std::vector<int> model;  // front: least recent
    std::mt19937 random(11);
    std::uint64_t frame = 0;
    for (int step = 0; step < 20000; ++step) {
        const int layer = static_cast<int>(random() % kLayers);
        const auto at = std::find(model.begin(), model.end(), layer);
        if (step % 7 == 0) ++frame;
        if (at == model.end()) {
            lru.insert(layer, frame);
            model.push_back(layer);
        } else if (random() % 3 == 0) {
            lru.remove(layer);
            model.erase(at);
        } else {
            lru.touch(layer, frame);
            model.erase(at);
            model.push_back(layer);
        }
        ASSERT_EQ(lru.size(), static_cast<int>(model.size()));
        if (model.empty()) {
            ASSERT_EQ(lru.leastRecent(), std::nullopt);
        } else {
            ASSERT_EQ(lru.leastRecent(), model.front());
        }
    }
}

}  // namespace
}  // namespace terrain::cache
