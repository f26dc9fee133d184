// Log-bucketed latency histogram (see LatencyHistogram.h).
#include "terrain/runtime/LatencyHistogram.h"

#include "terrain/base/Assert.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace terrain::runtime {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}  // namespace

std::size_t LatencyHistogram::bucketIndex(double ms) {
    // Written so that NaN-free values below kMinMs (and ≤ 0, where log10 is undefined)
    // never reach log10, and rounding at the top cannot step past the last bucket.
    if (!(ms > kMinMs)) return 0;
    if (ms >= kMaxMs) return kBucketCount - 1;
    const double position = std::log10(ms / kMinMs) * kBucketsPerDecade;
    return std::min(static_cast<std::size_t>(position), kBucketCount - 1);
}

double LatencyHistogram::bucketValueMs(std::size_t index) {
    TERRAIN_ASSERT(index < kBucketCount, "bucket index out of range");
    return kMinMs * std::pow(10.0, (static_cast<double>(index) + 0.5) / kBucketsPerDecade);
}

void LatencyHistogram::add(double ms) {
    TERRAIN_ASSERT(!std::isnan(ms), "LatencyHistogram::add(NaN)");
    ++m_buckets[bucketIndex(ms)];
    if (m_count == 0) {
        m_minMs = ms;
        m_maxMs = ms;
    } else {
        m_minMs = std::min(m_minMs, ms);
        m_maxMs = std::max(m_maxMs, ms);
    }
    ++m_count;
    m_sumMs += ms;
}

double LatencyHistogram::percentile(double p) const {
    TERRAIN_ASSERT(p >= 0.0 && p <= 100.0, "percentile p must be in [0, 100]");
    if (m_count == 0) return kNaN;
    // p · n / 100 rather than p / 100 · n: exact for integral p, so p = 95 of 100
    // samples is rank 95, not 96 after rounding 0.95 up.
    const double n = static_cast<double>(m_count);
    const auto rank = static_cast<std::uint64_t>(std::clamp(std::ceil(p * n / 100.0), 1.0, n));
    // The smallest and largest values are known exactly; a bucket value would be ~1 % off.
    if (rank == 1) return m_minMs;
    if (rank == m_count) return m_maxMs;
    std::uint64_t seen = 0;
    for (std::size_t i = 0; i < kBucketCount; ++i) {
        seen += m_buckets[i];
        if (seen >= rank) return std::clamp(bucketValueMs(i), m_minMs, m_maxMs);
    }
    TERRAIN_ASSERT(false, "bucket counts do not add up to count()");
    return kNaN;
}

double LatencyHistogram::max() const { return m_count == 0 ? kNaN : m_maxMs; }

double LatencyHistogram::min() const { return m_count == 0 ? kNaN : m_minMs; }

double LatencyHistogram::mean() const {
    return m_count == 0 ? kNaN : m_sumMs / static_cast<double>(m_count);
}

void LatencyHistogram::merge(const LatencyHistogram& other) {
    if (other.m_count == 0) return;
    for (std::size_t i = 0; i < kBucketCount; ++i) m_buckets[i] += other.m_buckets[i];
    m_minMs = m_count == 0 ? other.m_minMs : std::min(m_minMs, other.m_minMs);
    m_maxMs = m_count == 0 ? other.m_maxMs : std::max(m_maxMs, other.m_maxMs);
    m_count += other.m_count;
    m_sumMs += other.m_sumMs;
}

void LatencyHistogram::reset() {
    m_buckets.fill(0);
    m_count = 0;
    m_sumMs = 0.0;
    m_minMs = 0.0;
    m_maxMs = 0.0;
}

}  // namespace terrain::runtime
