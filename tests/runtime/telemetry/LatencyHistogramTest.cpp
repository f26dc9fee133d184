// LatencyHistogram: percentiles within its ~1 % resolution of the exact nearest-rank values,
// exact count/min/max/mean, NaN when empty, clamping into the end buckets, merge and reset.
#include "terrain/runtime/LatencyHistogram.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numeric>
#include <random>
#include <vector>

namespace terrain::runtime {
namespace {

// The nearest-rank percentile (the definition LatencyHistogram and LatencyWindow follow).
double exactPercentile(std::vector<double> values, double p) {
    std::sort(values.begin(), values.end());
    const double n = static_cast<double>(values.size());
    const auto rank = static_cast<std::size_t>(std::clamp(std::ceil(p * n / 100.0), 1.0, n));
    return values[rank - 1];
}

std::vector<double> lognormalSamples(std::size_t count, unsigned seed) {
    std::mt19937_64 random(seed);
    // Median e^2.5 ≈ 12 ms with a long tail: a plausible load-latency distribution.
    std::lognormal_distribution<double> distribution(2.5, 1.0);
    std::vector<double> samples(count);
    for (double& sample : samples) sample = distribution(random);
    return samples;
}

TEST(LatencyHistogram, EmptyIsNaN) {
    const LatencyHistogram histogram;
    EXPECT_EQ(histogram.count(), 0u);
    EXPECT_TRUE(std::isnan(histogram.percentile(0)));
    EXPECT_TRUE(std::isnan(histogram.percentile(50)));
    EXPECT_TRUE(std::isnan(histogram.percentile(100)));
    EXPECT_TRUE(std::isnan(histogram.max()));
    EXPECT_TRUE(std::isnan(histogram.min()));
    EXPECT_TRUE(std::isnan(histogram.mean()));
}

TEST(LatencyHistogram, PercentilesOfLognormalSamplesWithinOnePercent) {
    const std::vector<double> samples = lognormalSamples(10'000, 42);
    LatencyHistogram histogram;
    for (double sample : samples) histogram.add(sample);
    ASSERT_EQ(histogram.count(), samples.size());

    for (double p : {0.0, 0.1, 1.0, 10.0, 25.0, 50.0, 75.0, 90.0, 95.0, 99.0, 99.9, 100.0}) {
        const double exact = exactPercentile(samples, p);
        const double approx = histogram.percentile(p);
        EXPECT_LE(std::abs(approx / exact - 1.0), LatencyHistogram::kRelativeError)
            << "p" << p << ": exact " << exact << ", histogram " << approx;
        EXPECT_LT(std::abs(approx / exact - 1.0), 0.01) << "p" << p;
    }
    // The ends are clamped to the exact extremes.
    EXPECT_EQ(histogram.percentile(0), *std::min_element(samples.begin(), samples.end()));
    EXPECT_EQ(histogram.percentile(100), *std::max_element(samples.begin(), samples.end()));
    EXPECT_EQ(histogram.max(), *std::max_element(samples.begin(), samples.end()));
    EXPECT_EQ(histogram.min(), *std::min_element(samples.begin(), samples.end()));
    const double exactMean =
        std::accumulate(samples.begin(), samples.end(), 0.0) / static_cast<double>(samples.size());
    EXPECT_NEAR(histogram.mean(), exactMean, 1e-12 * exactMean);
}

TEST(LatencyHistogram, NearestRankOnAFewValues) {
    LatencyHistogram histogram;
    for (double ms : {4.0, 1.0, 3.0, 2.0}) histogram.add(ms);
    EXPECT_EQ(histogram.percentile(0), 1.0);
    EXPECT_NEAR(histogram.percentile(25), 1.0, 1.0 * LatencyHistogram::kRelativeError);
    EXPECT_NEAR(histogram.percentile(50), 2.0, 2.0 * LatencyHistogram::kRelativeError);
    EXPECT_NEAR(histogram.percentile(51), 3.0, 3.0 * LatencyHistogram::kRelativeError);
    EXPECT_NEAR(histogram.percentile(75), 3.0, 3.0 * LatencyHistogram::kRelativeError);
    EXPECT_EQ(histogram.percentile(100), 4.0);
    EXPECT_EQ(histogram.mean(), 2.5);
}

TEST(LatencyHistogram, EveryBucketValueIsWithinTheResolutionOfItsMembers) {
    for (std::size_t i = 0; i < LatencyHistogram::kBucketCount; ++i) {
        ASSERT_EQ(LatencyHistogram::bucketIndex(LatencyHistogram::bucketValueMs(i)), i);
    }
    // A dense sweep over the whole range, edges included.
    for (double ms = LatencyHistogram::kMinMs; ms < LatencyHistogram::kMaxMs; ms *= 1.001) {
        const double value = LatencyHistogram::bucketValueMs(LatencyHistogram::bucketIndex(ms));
        ASSERT_LE(std::abs(value / ms - 1.0), LatencyHistogram::kRelativeError + 1e-12) << ms;
    }
}

TEST(LatencyHistogram, OutOfRangeValuesClampIntoTheEndBuckets) {
    constexpr std::size_t kLast = LatencyHistogram::kBucketCount - 1;
    EXPECT_EQ(LatencyHistogram::bucketIndex(0.0), 0u);
    EXPECT_EQ(LatencyHistogram::bucketIndex(-3.0), 0u);
    EXPECT_EQ(LatencyHistogram::bucketIndex(1e-9), 0u);
    EXPECT_EQ(LatencyHistogram::bucketIndex(-std::numeric_limits<double>::infinity()), 0u);
    EXPECT_EQ(LatencyHistogram::bucketIndex(LatencyHistogram::kMinMs), 0u);
    EXPECT_EQ(LatencyHistogram::bucketIndex(LatencyHistogram::kMaxMs), kLast);
    EXPECT_EQ(LatencyHistogram::bucketIndex(1e12), kLast);
    EXPECT_EQ(LatencyHistogram::bucketIndex(std::numeric_limits<double>::infinity()), kLast);

    // All in the first bucket: the percentile is clamped to the exact range of the values.
    LatencyHistogram tiny;
    tiny.add(0.0);
    tiny.add(0.0);
    EXPECT_EQ(tiny.percentile(50), 0.0);
    tiny.add(-1.0);
    EXPECT_EQ(tiny.percentile(0), -1.0);
    EXPECT_EQ(tiny.percentile(100), 0.0);
    EXPECT_EQ(tiny.count(), 3u);
    EXPECT_NEAR(tiny.mean(), -1.0 / 3.0, 1e-15);

    // Far beyond the top: the last bucket, clamped to the values' range; max() exact.
    LatencyHistogram huge;
    huge.add(2e9);
    huge.add(3e9);
    EXPECT_EQ(huge.percentile(50), 2e9);
    EXPECT_EQ(huge.percentile(100), 3e9);
    EXPECT_EQ(huge.max(), 3e9);

    // Mixed: values below 1 µs read back as about 1 µs (their bucket), values above
    // 1000 s as about 1000 s, except the exact extremes.
    LatencyHistogram mixed;
    for (double ms : {-1.0, 0.0, 5.0, 2e9, 3e9}) mixed.add(ms);
    EXPECT_EQ(mixed.percentile(0), -1.0);
    EXPECT_NEAR(mixed.percentile(40), LatencyHistogram::kMinMs, LatencyHistogram::kMinMs * 0.01);
    EXPECT_NEAR(mixed.percentile(60), 5.0, 5.0 * LatencyHistogram::kRelativeError);
    EXPECT_NEAR(mixed.percentile(80), LatencyHistogram::kMaxMs, LatencyHistogram::kMaxMs * 0.01);
    EXPECT_EQ(mixed.percentile(100), 3e9);
}

TEST(LatencyHistogram, MergeEqualsAddingEverythingToOne) {
    const std::vector<double> a = lognormalSamples(3000, 1);
    const std::vector<double> b = lognormalSamples(500, 2);
    LatencyHistogram first;
    LatencyHistogram second;
    LatencyHistogram all;
    for (double ms : a) {
        first.add(ms);
        all.add(ms);
    }
    for (double ms : b) {
        second.add(ms);
        all.add(ms);
    }
    LatencyHistogram empty;
    empty.merge(first);  // merging into an empty histogram takes min/max from the other
    empty.merge(second);
    first.merge(second);
    first.merge(LatencyHistogram());  // merging nothing changes nothing
    for (const LatencyHistogram* merged : {&first, &empty}) {
        EXPECT_EQ(merged->count(), all.count());
        EXPECT_EQ(merged->min(), all.min());
        EXPECT_EQ(merged->max(), all.max());
        EXPECT_NEAR(merged->mean(), all.mean(), 1e-12 * all.mean());
        for (double p : {0.0, 50.0, 95.0, 99.0, 100.0}) {
            EXPECT_EQ(merged->percentile(p), all.percentile(p)) << p;
        }
    }
}

TEST(LatencyHistogram, ResetForgetsEverything) {
    LatencyHistogram histogram;
    histogram.add(5.0);
    histogram.add(7.0);
    histogram.reset();
    EXPECT_EQ(histogram.count(), 0u);
    EXPECT_TRUE(std::isnan(histogram.percentile(50)));
    EXPECT_TRUE(std::isnan(histogram.mean()));
    histogram.add(3.0);
    EXPECT_EQ(histogram.min(), 3.0);
    EXPECT_EQ(histogram.max(), 3.0);
    EXPECT_EQ(histogram.mean(), 3.0);
    EXPECT_EQ(histogram.percentile(50), 3.0);
}

}  // namespace
}  // namespace terrain::runtime
