// LatencyWindow: the most recent N latencies and exact percentiles over them, for the
// per-frame telemetry columns (load_latency_p50_ms ...) that should follow changes in a
// run rather than average over all of it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace terrain::runtime {

/// A ring of the last capacity() latencies in milliseconds. Memory is allocated once, in
/// the constructor; add() and percentile() never allocate. Not thread-safe: one thread at
/// a time (the render thread in the viewer and the stress tool).
class LatencyWindow {
public:
    static constexpr std::size_t kDefaultCapacity = 256;

    /// capacity ≥ 1.
    explicit LatencyWindow(std::size_t capacity = kDefaultCapacity);

    /// Adds one latency, dropping the oldest when the window is full. `ms` must not be NaN.
    void add(double ms);

    /// The exact nearest-rank p-th percentile of the latencies in the window, p in
    /// [0, 100]: the ceil(p / 100 · count())-th smallest (the smallest for p = 0). NaN when
    /// empty. O(count()) with std::nth_element on a scratch copy, which is why this is not
    /// const: the window keeps its arrival order for the ring.
    double percentile(double p);

    /// Latencies in the window: min(latencies added since construction or clear(),
    /// capacity()).
    std::size_t count() const { return m_count; }
    std::size_t capacity() const { return m_ring.size(); }

    /// Empties the window (keeps its memory).
    void clear();

private:
    std::vector<double> m_ring;     // capacity() slots, m_count of them valid
    std::vector<double> m_scratch;  // capacity() slots, reordered by percentile()
    std::size_t m_next = 0;         // slot add() writes next
    std::size_t m_count = 0;
};

}  // namespace terrain::runtime
