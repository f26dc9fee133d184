// Sliding window of recent latencies with exact percentiles (see LatencyWindow.h).
#include "terrain/runtime/LatencyWindow.h"

#include "terrain/base/Assert.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace terrain::runtime {

LatencyWindow::LatencyWindow(std::size_t capacity) : m_ring(capacity), m_scratch(capacity) {
    TERRAIN_ASSERT(capacity >= 1, "LatencyWindow needs a capacity of at least 1");
}

void LatencyWindow::add(double ms) {
    TERRAIN_ASSERT(!std::isnan(ms), "LatencyWindow::add(NaN)");
    m_ring[m_next] = ms;
    m_next = (m_next + 1) % m_ring.size();
    m_count = std::min(m_count + 1, m_ring.size());
}

double LatencyWindow::percentile(double p) {
    TERRAIN_ASSERT(p >= 0.0 && p <= 100.0, "percentile p must be in [0, 100]");
    if (m_count == 0) return std::numeric_limits<double>::quiet_NaN();
    // Until the ring wraps, the valid samples are its first m_count slots; afterwards all.
    std::copy_n(m_ring.begin(), m_count, m_scratch.begin());
    // p · n / 100 rather than p / 100 · n: exact for integral p (see LatencyHistogram).
    const double n = static_cast<double>(m_count);
    const auto rank = static_cast<std::size_t>(std::clamp(std::ceil(p * n / 100.0), 1.0, n));
    const auto end = m_scratch.begin() + static_cast<std::ptrdiff_t>(m_count);
    const auto nth = m_scratch.begin() + static_cast<std::ptrdiff_t>(rank - 1);
    std::nth_element(m_scratch.begin(), nth, end);
    return *nth;
}

void LatencyWindow::clear() {
    m_next = 0;
    m_count = 0;
}

}  // namespace terrain::runtime
