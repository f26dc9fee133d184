// FullDetailClock: the time to full detail after the camera arrives (terrain-render's globe
// flight, terrain-bench's FullDetailAfterArrival): the caller draws frames as a user sees
// them and hands each one's state here; the heights and the imagery are timed apart, each
// from the frame it reached full detail and stayed there (a finer patch may want finer
// imagery again).
#pragma once

#include "terrain/runtime/LodStrategy.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdint>

namespace terrain::tools {

class FullDetailClock {
public:
    FullDetailClock() : m_arrived(Clock::now()) {}

    /// After a frame ended: the heights are at full detail when no split waited for a tile
    /// (`waitingSplits`, from beginFrame) and nothing loads; the imagery when
    /// `strategy.imageryWaiting()` is 0.
    void frameEnded(const runtime::LodStrategy& strategy, std::uint64_t waitingSplits);

    /// Both at full detail in the last frame.
    bool reached() const { return !m_heights.is_null() && !m_imagery.is_null(); }
    double seconds() const;
    /// {"frames", "seconds", "heights": {"frames", "seconds"}, "imagery": {…}} once
    /// reached(), else null.
    nlohmann::json result() const;

private:
    using Clock = std::chrono::steady_clock;
    Clock::time_point m_arrived;
    std::uint64_t m_frames = 0;
    nlohmann::json m_heights, m_imagery;  // null while not at full detail
};

}  // namespace terrain::tools
