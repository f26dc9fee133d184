// End-of-run telemetry summary (see TelemetrySummary.h).
#include "terrain/runtime/TelemetrySummary.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>

namespace terrain::runtime {

namespace {

// nlohmann::json would write NaN as null anyway; saying so keeps the intent visible and
// does not depend on the dump settings.
nlohmann::json numberOrNull(double value) {
    return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

double ratioOrNaN(double numerator, double denominator) {
    return denominator > 0.0 ? numerator / denominator : std::nan("");
}

}  // namespace

void TelemetrySummary::add(const FrameTelemetry& frame) {
    const double frameS = std::isfinite(frame.frameMs) ? frame.frameMs / 1000.0 : 0.0;
    if (m_frames == 0) m_startS = frame.timeS - frameS;
    m_endS = frame.timeS;
    ++m_frames;

    m_requestsMade += frame.requestsMade;
    m_requestsCancelled += frame.requestsCancelled;
    m_requestsCompleted += frame.requestsCompleted;
    m_requestsFailed += frame.requestsFailed;
    m_cpuCacheHits += frame.cpuCacheHits;
    m_cpuCacheMisses += frame.cpuCacheMisses;
    m_cpuCacheEvictions += frame.cpuCacheEvictions;
    m_gpuEvictions += frame.gpuEvictions;
    m_gpuUploads += frame.gpuUploads;
    m_gpuUploadBytes += frame.gpuUploadBytes;
    m_gpuUploadsDeferred += frame.gpuUploadsDeferred;
    m_diskReadBytes += frame.diskReadBytes;
    m_storedBytesRead += frame.storedBytesRead;
    m_faults = std::max(m_faults, frame.faultsTotal);
    m_http.httpRequests += frame.httpRequests;
    m_http.httpRetries += frame.httpRetries;
    m_http.httpFetched += frame.httpFetched;
    m_http.httpFetchedBytes += frame.httpFetchedBytes;
    m_http.httpNotModified += frame.httpNotModified;
    m_http.httpCacheHits += frame.httpCacheHits;
    m_http.httpStaleServed += frame.httpStaleServed;

    m_peakQueueDepth = std::max(m_peakQueueDepth, frame.queueDepth);
    m_peakCpuCacheBytes = std::max(m_peakCpuCacheBytes, frame.cpuCacheBytes);
    m_peakGpuLayersUsed = std::max(m_peakGpuLayersUsed, frame.gpuLayersUsed);

    m_imageryRequestsMade += frame.imageryRequestsMade;
    m_imageryRequestsCancelled += frame.imageryRequestsCancelled;
    m_imageryRequestsCompleted += frame.imageryRequestsCompleted;
    m_imageryRequestsFailed += frame.imageryRequestsFailed;
    m_imageryGpuUploads += frame.imageryGpuUploads;
    m_imageryGpuUploadBytes += frame.imageryGpuUploadBytes;
    m_imageryGpuEvictions += frame.imageryGpuEvictions;
    m_imageryFaults = std::max(m_imageryFaults, frame.imageryFaultsTotal);
    m_peakImageryTilesResident = std::max(m_peakImageryTilesResident, frame.imageryTilesResident);
    m_peakImageryGpuBytes = std::max(m_peakImageryGpuBytes, frame.imageryGpuBytes);
    m_peakImageryCpuCacheBytes = std::max(m_peakImageryCpuCacheBytes, frame.imageryCpuCacheBytes);

    if (!std::isnan(frame.frameMs)) m_frameMs.add(frame.frameMs);
}

double TelemetrySummary::durationS() const { return m_frames == 0 ? 0.0 : m_endS - m_startS; }

nlohmann::json TelemetrySummary::toJson() const {
    using nlohmann::json;
    const double durationSeconds = durationS();
    const double lookups = static_cast<double>(m_cpuCacheHits + m_cpuCacheMisses);
    json summary;
    summary["frames"] = m_frames;
    summary["duration_s"] = durationSeconds;
    summary["throughput_tiles_per_s"] =
        numberOrNull(ratioOrNaN(static_cast<double>(m_requestsCompleted), durationSeconds));
    summary["totals"] = {
        {"requests_made", m_requestsMade},
        {"requests_cancelled", m_requestsCancelled},
        {"requests_completed", m_requestsCompleted},
        {"requests_failed", m_requestsFailed},
        {"cpu_cache_hits", m_cpuCacheHits},
        {"cpu_cache_misses", m_cpuCacheMisses},
        {"cpu_cache_hit_rate",
         numberOrNull(ratioOrNaN(static_cast<double>(m_cpuCacheHits), lookups))},
        {"cpu_cache_evictions", m_cpuCacheEvictions},
        {"gpu_evictions", m_gpuEvictions},
        {"gpu_uploads", m_gpuUploads},
        {"gpu_upload_bytes", m_gpuUploadBytes},
        {"gpu_uploads_deferred", m_gpuUploadsDeferred},
        {"disk_read_bytes", m_diskReadBytes},
        {"stored_bytes_read", m_storedBytesRead},
        {"faults", m_faults},
    };
    // Over HTTP: files the readers used, and how many of them the disk cache gave (without a
    // request, after a 304 and no body, or stale with the server out of reach).
    const std::uint64_t fromCache =
                            m_http.httpCacheHits + m_http.httpNotModified + m_http.httpStaleServed,
                        used = fromCache + m_http.httpFetched;
    summary["http"] = {
        {"requests", m_http.httpRequests},
        {"retries", m_http.httpRetries},
        {"files_fetched", m_http.httpFetched},
        {"fetched_bytes", m_http.httpFetchedBytes},
        {"not_modified", m_http.httpNotModified},
        {"cache_hits", m_http.httpCacheHits},
        {"stale_served", m_http.httpStaleServed},
        {"cache_hit_rate",
         numberOrNull(ratioOrNaN(static_cast<double>(fromCache), static_cast<double>(used)))},
        // Whole files come, so a view that needs a few patches of a shard pays for all of it.
        {"fetched_per_needed_byte",
         numberOrNull(m_http.httpRequests == 0
                          ? FrameTelemetry::kNoValue
                          : ratioOrNaN(static_cast<double>(m_http.httpFetchedBytes),
                                       static_cast<double>(m_storedBytesRead)))},
    };
    summary["peaks"] = {
        {"queue_depth", m_peakQueueDepth},
        {"cpu_cache_bytes", m_peakCpuCacheBytes},
        {"gpu_layers_used", m_peakGpuLayersUsed},
    };
    summary["imagery"] = {
        {"totals",
         {
             {"requests_made", m_imageryRequestsMade},
             {"requests_cancelled", m_imageryRequestsCancelled},
             {"requests_completed", m_imageryRequestsCompleted},
             {"requests_failed", m_imageryRequestsFailed},
             {"gpu_uploads", m_imageryGpuUploads},
             {"gpu_upload_bytes", m_imageryGpuUploadBytes},
             {"gpu_evictions", m_imageryGpuEvictions},
             {"faults", m_imageryFaults},
         }},
        {"peaks",
         {
             {"tiles_resident", m_peakImageryTilesResident},
             {"gpu_bytes", m_peakImageryGpuBytes},
             {"cpu_cache_bytes", m_peakImageryCpuCacheBytes},
         }},
    };
    summary["frame_ms"] = {
        {"p50", numberOrNull(m_frameMs.percentile(50))},
        {"p95", numberOrNull(m_frameMs.percentile(95))},
        {"p99", numberOrNull(m_frameMs.percentile(99))},
        {"max", numberOrNull(m_frameMs.max())},
    };
    summary["load_latency_ms"] = {
        {"count", m_loadLatencyMs.count()},
        {"p50", numberOrNull(m_loadLatencyMs.percentile(50))},
        {"p95", numberOrNull(m_loadLatencyMs.percentile(95))},
        {"p99", numberOrNull(m_loadLatencyMs.percentile(99))},
        {"max", numberOrNull(m_loadLatencyMs.max())},
        {"mean", numberOrNull(m_loadLatencyMs.mean())},
    };
    return summary;
}

}  // namespace terrain::runtime
