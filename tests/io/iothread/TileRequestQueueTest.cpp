// TileRequestQueue: highest priority first, ties first come first served, re-prioritising,
// cancelling, no allocation once warm, and agreement with a brute-force model under a
// seeded random sequence.
#include "terrain/iothread/TileRequestQueue.h"

#include "AllocationCounter.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <optional>
#include <random>
#include <vector>

namespace terrain::io {
namespace {

PatchId patch(std::int64_t x) { return PatchId{3, x, 0}; }

std::vector<std::int64_t> drain(TileRequestQueue& queue) {
    std::vector<std::int64_t> order;
    while (auto r = queue.popHighest()) order.push_back(r->id.x);
    return order;
}

TEST(TileRequestQueueTest, PopsHighestPriorityFirst) {
    TileRequestQueue queue;
    EXPECT_TRUE(queue.request(patch(0), 1.0f));
    EXPECT_TRUE(queue.request(patch(1), 5.0f));
    EXPECT_TRUE(queue.request(patch(2), -2.0f));
    EXPECT_TRUE(queue.request(patch(3), 3.5f));
    EXPECT_EQ(queue.size(), 4U);
    const auto top = queue.popHighest();
    ASSERT_TRUE(top.has_value());
    EXPECT_EQ(top->id, patch(1));
    EXPECT_EQ(top->priority, 5.0f);
    EXPECT_EQ(drain(queue), (std::vector<std::int64_t>{3, 0, 2}));
    EXPECT_TRUE(queue.empty());
    EXPECT_FALSE(queue.popHighest().has_value());
}

TEST(TileRequestQueueTest, BreaksTiesFirstInFirstOut) {
    TileRequestQueue queue;
    for (std::int64_t x : {4, 2, 7, 1, 9}) EXPECT_TRUE(queue.request(patch(x), 2.0f));
    EXPECT_TRUE(queue.request(patch(5), 3.0f));
    EXPECT_EQ(drain(queue), (std::vector<std::int64_t>{5, 4, 2, 7, 1, 9}));
}

TEST(TileRequestQueueTest, RequestAgainReprioritisesAndKeepsArrival) {
    TileRequestQueue queue;
    EXPECT_TRUE(queue.request(patch(0), 1.0f));
    EXPECT_TRUE(queue.request(patch(1), 2.0f));
    EXPECT_TRUE(queue.request(patch(2), 3.0f));
    EXPECT_FALSE(queue.request(patch(0), 10.0f));  // not new: moved up
    EXPECT_EQ(queue.size(), 3U);
    EXPECT_EQ(queue.priority(patch(0)), 10.0f);
    EXPECT_FALSE(queue.request(patch(2), 0.5f));  // moved down
    EXPECT_EQ(drain(queue), (std::vector<std::int64_t>{0, 1, 2}));

    // Among equal priorities a re-prioritised request keeps its first arrival.
    EXPECT_TRUE(queue.request(patch(7), 1.0f));
    EXPECT_TRUE(queue.request(patch(8), 2.0f));
    EXPECT_FALSE(queue.request(patch(8), 1.0f));
    EXPECT_FALSE(queue.request(patch(7), 1.0f));
    EXPECT_EQ(drain(queue), (std::vector<std::int64_t>{7, 8}));
}

TEST(TileRequestQueueTest, CancelRemovesOnlyThatRequest) {
    TileRequestQueue queue;
    for (std::int64_t x = 0; x < 5; ++x)
        EXPECT_TRUE(queue.request(patch(x), static_cast<float>(x)));
    EXPECT_TRUE(queue.contains(patch(2)));
    EXPECT_TRUE(queue.cancel(patch(2)));
    EXPECT_FALSE(queue.contains(patch(2)));
    EXPECT_FALSE(queue.cancel(patch(2)));
    EXPECT_FALSE(queue.cancel(PatchId{0, 2, 0}));  // other level, never requested
    EXPECT_FALSE(queue.priority(patch(2)).has_value());
    EXPECT_EQ(queue.size(), 4U);
    EXPECT_EQ(drain(queue), (std::vector<std::int64_t>{4, 3, 1, 0}));
    // A cancelled id can be requested again, as a new request.
    EXPECT_TRUE(queue.request(patch(2), 1.0f));
    EXPECT_EQ(queue.size(), 1U);
    queue.clear();
    EXPECT_TRUE(queue.empty());
    EXPECT_FALSE(queue.contains(patch(2)));
}

constexpr std::int64_t kChurnPatches = 64;

struct ChurnTally {
    std::uint64_t created = 0;
    std::uint64_t reprioritised = 0;
    std::uint64_t cancelled = 0;
    std::uint64_t popped = 0;
};

// A render loop's use of the queue: each frame requests and re-prioritises patches of a
// window of kChurnPatches, cancels some that left the view, and the I/O thread pops;
// now and then everything is dropped (clear).
void churn(TileRequestQueue& queue, std::mt19937& rng, ChurnTally& tally) {
    for (int step = 0; step < 5000; ++step) {
        const PatchId id = patch(static_cast<std::int64_t>(rng() % kChurnPatches));
        const auto op = rng() % 10;
        if (op < 5) {
            if (queue.request(id, static_cast<float>(rng() % 8))) {
                ++tally.created;
            } else {
                ++tally.reprioritised;
            }
        } else if (op < 7) {
            if (queue.cancel(id)) ++tally.cancelled;
        } else if (op < 9) {
            if (queue.popHighest()) ++tally.popped;
        } else if (step % 500 == 0) {
            queue.clear();
        }
    }
}

TEST(TileRequestQueueTest, AllocatesNothingOnceWarm) {
    TileRequestQueue queue;
    std::mt19937 rng(42);
    ChurnTally warmTally;
    {
        const terrain::test::AllocationScope warmUp;
        // The high-water size: every patch the churn uses, pending at once.
        for (std::int64_t x = 0; x < kChurnPatches; ++x) queue.request(patch(x), 1.0f);
        churn(queue, rng, warmTally);
        EXPECT_GT(warmUp.allocations(), 0u) << "the counter must see the queue's nodes";
    }

    ChurnTally tally;
    std::uint64_t allocations = 0;
    {
        const terrain::test::AllocationScope scope;
        churn(queue, rng, tally);
        allocations = scope.allocations();
    }
    EXPECT_EQ(allocations, 0u);
    // The round did exercise every path.
    EXPECT_GT(tally.created, 500u);
    EXPECT_GT(tally.reprioritised, 500u);
    EXPECT_GT(tally.cancelled, 200u);
    EXPECT_GT(tally.popped, 500u);
}

TEST(TileRequestQueueTest, AgreesWithBruteForceModel) {
    struct ModelEntry {
        PatchId id;
        float priority;
        std::uint64_t arrival;
    };
    std::vector<ModelEntry> model;
    std::uint64_t arrivals = 0;
    TileRequestQueue queue;
    std::mt19937 rng(1234);
    for (int step = 0; step < 20000; ++step) {
        const PatchId id{static_cast<int>(rng() % 3), static_cast<std::int64_t>(rng() % 8),
                         static_cast<std::int64_t>(rng() % 8)};
        const auto found = std::find_if(model.begin(), model.end(),
                                        [&](const ModelEntry& e) { return e.id == id; });
        const auto op = rng() % 10;
        if (op < 5) {
            const auto priority = static_cast<float>(rng() % 6);  // many ties
            EXPECT_EQ(queue.request(id, priority), found == model.end());
            if (found == model.end())
                model.push_back({id, priority, arrivals++});
            else
                found->priority = priority;
        } else if (op < 7) {
            EXPECT_EQ(queue.cancel(id), found != model.end());
            if (found != model.end()) model.erase(found);
        } else {
            const auto best = std::min_element(
                model.begin(), model.end(), [](const ModelEntry& a, const ModelEntry& b) {
                    return a.priority != b.priority ? a.priority > b.priority
                                                    : a.arrival < b.arrival;
                });
            const auto popped = queue.popHighest();
            ASSERT_EQ(popped.has_value(), best != model.end());
            if (popped) {
                EXPECT_EQ(popped->id, best->id);
                EXPECT_EQ(popped->priority, best->priority);
                model.erase(best);
            }
        }
        ASSERT_EQ(queue.size(), model.size());
        EXPECT_EQ(queue.contains(id), std::any_of(model.begin(), model.end(),
                                                  [&](const ModelEntry& e) { return e.id == id; }));
    }
}

}  // namespace
}  // namespace terrain::io
