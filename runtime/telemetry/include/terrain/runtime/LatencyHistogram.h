// LatencyHistogram: a fixed-memory histogram of latencies in milliseconds with log-spaced
// buckets, for percentiles over a whole run (the telemetry summary) where keeping every
// sample would grow without bound.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace terrain::runtime {

/// Counts latencies in kBucketCount buckets spaced evenly in log10 from kMinMs (1 µs) to
/// kMaxMs (1000 s), kBucketsPerDecade per decade: a bucket spans a factor of 10^(1/128) ≈
/// 1.018, so its representative value (the geometric middle) is within 0.9 % of any value
/// in it. Values below kMinMs (zero and negative included) count in the first bucket,
/// values at or above kMaxMs in the last. count(), max(), min() and mean() are exact.
///
/// No allocation at all (the buckets are a std::array, about 9 KiB). Not thread-safe: one
/// thread at a time (the render thread in the viewer and the stress tool).
class LatencyHistogram {
public:
    static constexpr double kMinMs = 1e-3;  ///< 1 µs: lower edge of the first bucket
    static constexpr double kMaxMs = 1e6;   ///< 1000 s: upper edge of the last bucket
    static constexpr int kDecades = 9;      ///< log10(kMaxMs / kMinMs)
    static constexpr int kBucketsPerDecade = 128;
    static constexpr std::size_t kBucketCount = std::size_t(kDecades) * kBucketsPerDecade;
    /// Bound on the relative distance of a percentile from the exact nearest-rank value,
    /// for values inside [kMinMs, kMaxMs): half a bucket in log space, 10^(1/256) − 1.
    static constexpr double kRelativeError = 0.00904;

    /// Counts one latency. `ms` must not be NaN (a NaN latency is a bug in the caller).
    void add(double ms);

    /// Latencies added since construction or reset(), merged ones included.
    std::uint64_t count() const { return m_count; }

    /// The nearest-rank p-th percentile, p in [0, 100]: the representative value of the
    /// bucket holding the ceil(p / 100 · count())-th smallest latency (the smallest for
    /// p = 0), clamped to [min(), max()]; exactly min() or max() for the first and last
    /// rank. NaN when empty. O(kBucketCount).
    double percentile(double p) const;

    /// Largest and smallest latency added, exactly; NaN when empty.
    double max() const;
    double min() const;
    /// Exact arithmetic mean (running sum / count); NaN when empty.
    double mean() const;

    /// Adds every latency counted by `other` to this histogram.
    void merge(const LatencyHistogram& other);

    /// Forgets every latency.
    void reset();

    /// The bucket `ms` counts in (0 to kBucketCount − 1); for tests and plots.
    static std::size_t bucketIndex(double ms);
    /// The representative value of bucket `index`: the geometric middle of its edges.
    static double bucketValueMs(std::size_t index);

private:
    std::array<std::uint64_t, kBucketCount> m_buckets{};
    std::uint64_t m_count = 0;
    double m_sumMs = 0.0;
    double m_minMs = 0.0;  // valid when m_count > 0
    double m_maxMs = 0.0;  // valid when m_count > 0
};

}  // namespace terrain::runtime
