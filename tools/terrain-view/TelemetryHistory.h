// TelemetryHistory: the last few seconds of frame telemetry for the overlay — the rolling
// plots and the rates that need more than one frame (frames per second, cache hit rate).
#pragma once

#include "terrain/runtime/FrameTelemetry.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>

namespace terrain::view {

/// A fixed ring of the most recent frames; add() never allocates. Render thread only.
class TelemetryHistory {
public:
    static constexpr std::size_t kFrames = 240;

    void add(const runtime::FrameTelemetry& frame);
    void clear();

    std::size_t size() const { return m_count; }
    bool empty() const { return m_count == 0; }
    /// The newest frame (undefined when empty()).
    const runtime::FrameTelemetry& latest() const;

    /// Frames per second over the newest frames spanning up to `windowS` seconds.
    std::optional<double> framesPerSecond(double windowS = 0.5) const;
    /// Mean frame_ms over the same window.
    std::optional<double> meanFrameMs(double windowS = 0.5) const;
    /// cpu_cache_hits / (hits + misses) over the whole history; nullopt without lookups.
    std::optional<double> cacheHitRate() const;
    /// The newest non-NaN gpu_ms, and the newest frame's triangles that were measured (> 0).
    std::optional<double> latestGpuMs() const;
    std::optional<std::uint64_t> latestTriangles() const;

    /// Plot series, oldest first, in a buffer ImGui::PlotLines reads directly.
    const float* frameMsSeries() const { return m_frameMs.data(); }
    const float* lodUsSeries() const { return m_lodUs.data(); }
    const float* queueDepthSeries() const { return m_queueDepth.data(); }
    /// Offset of the oldest value in the series above (ImGui's values_offset).
    int seriesOffset() const { return static_cast<int>(m_count < kFrames ? 0 : m_next); }
    int seriesCount() const { return static_cast<int>(m_count); }

private:
    const runtime::FrameTelemetry& at(std::size_t ageFromNewest) const;

    std::array<runtime::FrameTelemetry, kFrames> m_frames{};
    std::array<float, kFrames> m_frameMs{};
    std::array<float, kFrames> m_lodUs{};
    std::array<float, kFrames> m_queueDepth{};
    std::size_t m_next = 0;
    std::size_t m_count = 0;
};

}  // namespace terrain::view
