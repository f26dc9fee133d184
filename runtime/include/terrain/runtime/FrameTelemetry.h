// FrameTelemetry: one frame's streaming and cache counters, the row of the cache telemetry
// log, and the table of its CSV columns. The column names are user-facing and stable
// (docs/telemetry.md); units are in the names.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <string_view>

namespace terrain::runtime {

/// One frame's telemetry. Counts are "this frame" unless the comment says cumulative or
/// "at the end of the frame" (a level, not a count). The producer fills every field; NaN
/// doubles mean "no value yet" and are written as empty CSV fields.
struct FrameTelemetry {
    static constexpr double kNoValue = std::numeric_limits<double>::quiet_NaN();

    std::uint64_t frame = 0;  ///< frame number, from 0
    double timeS = 0.0;       ///< seconds from the start of the run to the end of this frame
    double frameMs = 0.0;     ///< wall time of this frame (end of previous to end of this)

    std::uint64_t requestsMade = 0;       ///< tile requests submitted
    std::uint64_t requestsCancelled = 0;  ///< requests that ended cancelled
    std::uint64_t requestsCompleted = 0;  ///< requests that ended with a tile
    std::uint64_t requestsFailed = 0;     ///< requests that ended with an error
    std::uint64_t queueDepth = 0;         ///< requests waiting, at the end of the frame
    std::uint64_t ioInFlight = 0;         ///< requests being read, at the end of the frame

    std::uint64_t cpuCacheHits = 0;
    std::uint64_t cpuCacheMisses = 0;
    std::uint64_t cpuCacheEvictions = 0;    ///< entries dropped to meet the byte budget
    std::uint64_t cpuCacheEntries = 0;      ///< at the end of the frame
    std::uint64_t cpuCacheBytes = 0;        ///< at the end of the frame
    std::uint64_t cpuCacheBudgetBytes = 0;  ///< at the end of the frame

    std::uint64_t gpuLayersUsed = 0;  ///< texture-array layers holding a tile, end of frame
    std::uint64_t gpuLayersFree = 0;  ///< at the end of the frame
    std::uint64_t gpuEvictions = 0;   ///< layers taken from a resident tile for another
    std::uint64_t gpuUploads = 0;
    std::uint64_t gpuUploadBytes = 0;
    std::uint64_t gpuUploadsDeferred = 0;  ///< refused by the per-frame upload budget
    std::uint64_t gpuRingStalls = 0;       ///< waits of the CPU for the GPU to free ring bytes

    std::uint64_t loadsResident = 0;  ///< requests that became GPU-resident this frame
    /// Request → resident latency percentiles over the last 256 loads (LatencyWindow);
    /// NaN until the first load.
    double loadLatencyP50Ms = kNoValue;
    double loadLatencyP95Ms = kNoValue;
    double loadLatencyP99Ms = kNoValue;

    std::uint64_t diskReadBytes = 0;  ///< bytes the I/O thread read this frame
    std::uint64_t faultsTotal = 0;    ///< cumulative: tiles that failed to load so far

    std::uint64_t patchesDrawn = 0;
    std::uint64_t patchesCulled = 0;
};

/// How a column's value is stored and written.
enum class TelemetryValueKind {
    Count,  ///< std::uint64_t, written as a decimal integer
    Real,   ///< double, written shortest round-trip; NaN as an empty field
};

/// One CSV column: its name and the FrameTelemetry member it shows (the one matching kind;
/// the other is null).
struct TelemetryColumn {
    std::string_view name;
    TelemetryValueKind kind = TelemetryValueKind::Count;
    std::uint64_t FrameTelemetry::*count = nullptr;
    double FrameTelemetry::*real = nullptr;
};

namespace detail {
constexpr TelemetryColumn countColumn(std::string_view name,
                                      std::uint64_t FrameTelemetry::*member) {
    return {name, TelemetryValueKind::Count, member, nullptr};
}
constexpr TelemetryColumn realColumn(std::string_view name, double FrameTelemetry::*member) {
    return {name, TelemetryValueKind::Real, nullptr, member};
}
}  // namespace detail

/// The CSV columns in file order; the header row and every data row iterate this one table,
/// so a new column is one line here (plus its member above and its row in
/// docs/telemetry.md). Columns are only ever appended: scripts may index them by position.
inline constexpr std::array kTelemetryColumns = {
    detail::countColumn("frame", &FrameTelemetry::frame),
    detail::realColumn("time_s", &FrameTelemetry::timeS),
    detail::realColumn("frame_ms", &FrameTelemetry::frameMs),
    detail::countColumn("requests_made", &FrameTelemetry::requestsMade),
    detail::countColumn("requests_cancelled", &FrameTelemetry::requestsCancelled),
    detail::countColumn("requests_completed", &FrameTelemetry::requestsCompleted),
    detail::countColumn("requests_failed", &FrameTelemetry::requestsFailed),
    detail::countColumn("queue_depth", &FrameTelemetry::queueDepth),
    detail::countColumn("io_in_flight", &FrameTelemetry::ioInFlight),
    detail::countColumn("cpu_cache_hits", &FrameTelemetry::cpuCacheHits),
    detail::countColumn("cpu_cache_misses", &FrameTelemetry::cpuCacheMisses),
    detail::countColumn("cpu_cache_evictions", &FrameTelemetry::cpuCacheEvictions),
    detail::countColumn("cpu_cache_entries", &FrameTelemetry::cpuCacheEntries),
    detail::countColumn("cpu_cache_bytes", &FrameTelemetry::cpuCacheBytes),
    detail::countColumn("cpu_cache_budget_bytes", &FrameTelemetry::cpuCacheBudgetBytes),
    detail::countColumn("gpu_layers_used", &FrameTelemetry::gpuLayersUsed),
    detail::countColumn("gpu_layers_free", &FrameTelemetry::gpuLayersFree),
    detail::countColumn("gpu_evictions", &FrameTelemetry::gpuEvictions),
    detail::countColumn("gpu_uploads", &FrameTelemetry::gpuUploads),
    detail::countColumn("gpu_upload_bytes", &FrameTelemetry::gpuUploadBytes),
    detail::countColumn("gpu_uploads_deferred", &FrameTelemetry::gpuUploadsDeferred),
    detail::countColumn("gpu_ring_stalls", &FrameTelemetry::gpuRingStalls),
    detail::countColumn("loads_resident", &FrameTelemetry::loadsResident),
    detail::realColumn("load_latency_p50_ms", &FrameTelemetry::loadLatencyP50Ms),
    detail::realColumn("load_latency_p95_ms", &FrameTelemetry::loadLatencyP95Ms),
    detail::realColumn("load_latency_p99_ms", &FrameTelemetry::loadLatencyP99Ms),
    detail::countColumn("disk_read_bytes", &FrameTelemetry::diskReadBytes),
    detail::countColumn("faults_total", &FrameTelemetry::faultsTotal),
    detail::countColumn("patches_drawn", &FrameTelemetry::patchesDrawn),
    detail::countColumn("patches_culled", &FrameTelemetry::patchesCulled),
};

namespace detail {
constexpr bool columnsAreDistinct() {
    for (std::size_t i = 0; i < kTelemetryColumns.size(); ++i) {
        for (std::size_t j = i + 1; j < kTelemetryColumns.size(); ++j) {
            const TelemetryColumn& a = kTelemetryColumns[i];
            const TelemetryColumn& b = kTelemetryColumns[j];
            if (a.name == b.name) return false;
            if (a.kind == b.kind && a.count == b.count && a.real == b.real) return false;
        }
    }
    return true;
}
}  // namespace detail

static_assert(detail::columnsAreDistinct(), "two telemetry columns share a name or a member");
// Every member is 8 bytes, so this catches a member added without its column (or the other
// way round). Adjust it if a member of another size is ever added.
static_assert(sizeof(FrameTelemetry) == kTelemetryColumns.size() * 8,
              "every FrameTelemetry member needs a column in kTelemetryColumns");

/// The CSV columns in file order.
constexpr std::span<const TelemetryColumn> telemetryColumns() { return kTelemetryColumns; }

}  // namespace terrain::runtime
