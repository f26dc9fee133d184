// TelemetrySummary: the end-of-run summary of the cache telemetry log (totals, peaks,
// frame-time and load-latency percentiles) as one JSON object for the --json output of the
// streaming stress tool and the viewer. Keys are user-facing and stable (docs/telemetry.md).
#pragma once

#include "terrain/runtime/FrameTelemetry.h"
#include "terrain/runtime/LatencyHistogram.h"

#include <nlohmann/json_fwd.hpp>

#include <cstdint>

namespace terrain::runtime {

/// Accumulates FrameTelemetry rows and individual load latencies. add() and
/// addLoadLatency() never allocate (the histograms are fixed arrays). Not thread-safe: one
/// thread at a time (the render thread in the viewer and the stress tool).
class TelemetrySummary {
public:
    /// Adds one frame: sums its per-frame counts, keeps peaks of its levels, the last
    /// cumulative faults_total, and its frame_ms (when not NaN) in the frame-time histogram.
    /// Frames are expected in order.
    void add(const FrameTelemetry& frame);

    /// Adds one request → resident latency; every load, not only the last 256 of the CSV
    /// column. `ms` must not be NaN.
    void addLoadLatency(double ms) { m_loadLatencyMs.add(ms); }
    /// Adds every latency of `latencies` (e.g. the TileStreamer's record of all its loads).
    void mergeLoadLatencies(const LatencyHistogram& latencies) { m_loadLatencyMs.merge(latencies); }

    std::uint64_t frameCount() const { return m_frames; }
    /// Seconds from the start of the first frame added (its time_s − frame_ms) to the end
    /// of the last (its time_s); 0 before the first frame.
    double durationS() const;
    const LatencyHistogram& frameMs() const { return m_frameMs; }
    const LatencyHistogram& loadLatencyMs() const { return m_loadLatencyMs; }

    /// The summary object; the keys are listed in docs/telemetry.md. Values that do not
    /// exist yet (percentiles of nothing, a hit rate with no lookups, a throughput over no
    /// time) are null.
    nlohmann::json toJson() const;

private:
    std::uint64_t m_frames = 0;
    double m_startS = 0.0;  // start of the first frame
    double m_endS = 0.0;    // end of the last frame

    std::uint64_t m_requestsMade = 0;
    std::uint64_t m_requestsCancelled = 0;
    std::uint64_t m_requestsCompleted = 0;
    std::uint64_t m_requestsFailed = 0;
    std::uint64_t m_cpuCacheHits = 0;
    std::uint64_t m_cpuCacheMisses = 0;
    std::uint64_t m_cpuCacheEvictions = 0;
    std::uint64_t m_gpuEvictions = 0;
    std::uint64_t m_gpuUploads = 0;
    std::uint64_t m_gpuUploadBytes = 0;
    std::uint64_t m_gpuUploadsDeferred = 0;
    std::uint64_t m_diskReadBytes = 0;
    std::uint64_t m_storedBytesRead = 0;
    std::uint64_t m_faults = 0;  // faults_total is cumulative: the latest, not a sum
    std::uint64_t m_imageryRequestsMade = 0;
    std::uint64_t m_imageryRequestsCancelled = 0;
    std::uint64_t m_imageryRequestsCompleted = 0;
    std::uint64_t m_imageryRequestsFailed = 0;
    std::uint64_t m_imageryGpuUploads = 0;
    std::uint64_t m_imageryGpuUploadBytes = 0;
    std::uint64_t m_imageryGpuEvictions = 0;
    std::uint64_t m_imageryFaults = 0;
    std::uint64_t m_peakImageryTilesResident = 0;
    std::uint64_t m_peakImageryGpuBytes = 0;
    std::uint64_t m_peakImageryCpuCacheBytes = 0;

    FrameTelemetry m_http;  // the http_* counts summed (addStreamingCounts)
    std::uint64_t m_peakQueueDepth = 0;
    std::uint64_t m_peakCpuCacheBytes = 0;
    std::uint64_t m_peakGpuLayersUsed = 0;

    LatencyHistogram m_frameMs;
    LatencyHistogram m_loadLatencyMs;
};

}  // namespace terrain::runtime
