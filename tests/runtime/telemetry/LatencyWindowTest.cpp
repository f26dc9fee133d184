// LatencyWindow: exact nearest-rank percentiles over the last N latencies, checked against a
// sorted copy of a std::deque model through many wraps of the ring.
#include "terrain/runtime/LatencyWindow.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <deque>
#include <random>
#include <vector>

namespace terrain::runtime {
namespace {

double exactPercentile(const std::deque<double>& window, double p) {
    std::vector<double> values(window.begin(), window.end());
    std::sort(values.begin(), values.end());
    const double n = static_cast<double>(values.size());
    const auto rank = static_cast<std::size_t>(std::clamp(std::ceil(p * n / 100.0), 1.0, n));
    return values[rank - 1];
}

TEST(LatencyWindow, EmptyIsNaN) {
    LatencyWindow window;
    EXPECT_EQ(window.capacity(), 256u);
    EXPECT_EQ(window.count(), 0u);
    EXPECT_TRUE(std::isnan(window.percentile(0)));
    EXPECT_TRUE(std::isnan(window.percentile(50)));
    EXPECT_TRUE(std::isnan(window.percentile(100)));
}

TEST(LatencyWindow, NearestRankBeforeTheWindowFills) {
    LatencyWindow window(8);
    for (double ms : {40.0, 10.0, 30.0, 20.0}) window.add(ms);
    EXPECT_EQ(window.count(), 4u);
    EXPECT_EQ(window.percentile(0), 10.0);
    EXPECT_EQ(window.percentile(25), 10.0);
    EXPECT_EQ(window.percentile(26), 20.0);
    EXPECT_EQ(window.percentile(50), 20.0);
    EXPECT_EQ(window.percentile(75), 30.0);
    EXPECT_EQ(window.percentile(99), 40.0);
    EXPECT_EQ(window.percentile(100), 40.0);
}

TEST(LatencyWindow, KeepsOnlyTheLastCapacityLatencies) {
    LatencyWindow window;  // 256
    for (int i = 1; i <= 1000; ++i) window.add(i);
    // The window holds 745 ... 1000.
    EXPECT_EQ(window.count(), 256u);
    EXPECT_EQ(window.percentile(0), 745.0);
    EXPECT_EQ(window.percentile(50), 745.0 + 127.0);  // rank 128
    EXPECT_EQ(window.percentile(95), 745.0 + 243.0);  // rank ceil(243.2) = 244
    EXPECT_EQ(window.percentile(100), 1000.0);
}

TEST(LatencyWindow, MatchesASortedModelThroughManyWraps) {
    std::mt19937 random(7);
    std::lognormal_distribution<double> latency(2.0, 1.2);
    std::uniform_real_distribution<double> percentile(0.0, 100.0);
    for (std::size_t capacity : {std::size_t(1), std::size_t(5), std::size_t(256)}) {
        LatencyWindow window(capacity);
        std::deque<double> model;
        for (int step = 0; step < 3000; ++step) {
            const double ms = latency(random);
            window.add(ms);
            model.push_back(ms);
            if (model.size() > capacity) model.pop_front();
            ASSERT_EQ(window.count(), model.size());
            // percentile() reorders its scratch copy only: the ring must stay intact.
            for (double p : {0.0, 50.0, 95.0, 99.0, 100.0, percentile(random)}) {
                ASSERT_EQ(window.percentile(p), exactPercentile(model, p))
                    << "capacity " << capacity << ", step " << step << ", p" << p;
            }
        }
    }
}

TEST(LatencyWindow, ClearEmptiesTheWindow) {
    LatencyWindow window(4);
    for (double ms : {1.0, 2.0, 3.0, 4.0, 5.0}) window.add(ms);
    window.clear();
    EXPECT_EQ(window.count(), 0u);
    EXPECT_TRUE(std::isnan(window.percentile(50)));
    window.add(9.0);
    EXPECT_EQ(window.count(), 1u);
    EXPECT_EQ(window.percentile(0), 9.0);
    EXPECT_EQ(window.percentile(100), 9.0);
}

}  // namespace
}  // namespace terrain::runtime
