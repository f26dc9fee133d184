// Ring buffer of recent frame telemetry and the overlay's rolling figures.
#include "TelemetryHistory.h"

#include <cmath>

namespace terrain::view {

void TelemetryHistory::add(const runtime::FrameTelemetry& frame) {
    m_frames[m_next] = frame;
    m_frameMs[m_next] = static_cast<float>(frame.frameMs);
    m_lodUs[m_next] = std::isnan(frame.lodUpdateUs) ? 0.0f : static_cast<float>(frame.lodUpdateUs);
    m_queueDepth[m_next] = static_cast<float>(frame.queueDepth);
    m_next = (m_next + 1) % kFrames;
    if (m_count < kFrames) ++m_count;
}

void TelemetryHistory::clear() {
    m_next = 0;
    m_count = 0;
}

const runtime::FrameTelemetry& TelemetryHistory::at(std::size_t ageFromNewest) const {
    return m_frames[(m_next + kFrames - 1 - ageFromNewest) % kFrames];
}

const runtime::FrameTelemetry& TelemetryHistory::latest() const { return at(0); }

std::optional<double> TelemetryHistory::meanFrameMs(double windowS) const {
    double sumMs = 0.0;
    std::size_t frames = 0;
    for (std::size_t age = 0; age < m_count; ++age) {
        sumMs += at(age).frameMs;
        ++frames;
        if (sumMs >= windowS * 1000.0) break;
    }
    if (frames == 0 || sumMs <= 0.0) return std::nullopt;
    return sumMs / static_cast<double>(frames);
}

std::optional<double> TelemetryHistory::framesPerSecond(double windowS) const {
    const std::optional<double> ms = meanFrameMs(windowS);
    if (!ms) return std::nullopt;
    return 1000.0 / *ms;
}

std::optional<double> TelemetryHistory::cacheHitRate() const {
    std::uint64_t hits = 0, lookups = 0;
    for (std::size_t age = 0; age < m_count; ++age) {
        hits += at(age).cpuCacheHits;
        lookups += at(age).cpuCacheHits + at(age).cpuCacheMisses;
    }
    if (lookups == 0) return std::nullopt;
    return static_cast<double>(hits) / static_cast<double>(lookups);
}

std::optional<double> TelemetryHistory::latestGpuMs() const {
    for (std::size_t age = 0; age < m_count; ++age) {
        if (!std::isnan(at(age).gpuMs)) return at(age).gpuMs;
    }
    return std::nullopt;
}

std::optional<std::uint64_t> TelemetryHistory::latestTriangles() const {
    for (std::size_t age = 0; age < m_count; ++age) {
        if (at(age).triangles > 0) return at(age).triangles;
    }
    return std::nullopt;
}

}  // namespace terrain::view
