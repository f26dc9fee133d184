// FullDetailClock: the time to full detail after the camera arrives (terrain-render's globe
// flight, terrain-bench's FullDetailAfterArrival): the caller draws frames as a user sees
// them and hands each one's state here; the heights and the imagery are timed apart, each
// from the frame it reached full detail and stayed there (a finer patch may want finer
// imagery again).
#pragma once

#include "FramePacer.h"
#include "terrain/runtime/LodStrategy.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdint>

namespace terrain::tools {

/// The shortest time between two frames of an arrival: a 60 Hz display's.
inline constexpr double kArrivalFrameS = 1.0 / 60.0;

class FullDetailClock {
public:
    FullDetailClock() : m_arrived(Clock::now()) {}

    /// After a frame ended: the heights are at full detail when no split waited for a tile
    /// (`waitingSplits`, from beginFrame) and nothing loads; the imagery when
    /// `strategy.imageryWaiting()` is 0.
    void frameEnded(const runtime::LodStrategy& strategy, std::uint64_t waitingSplits);

    /// Before each frame: waits until kArrivalFrameS has passed since the previous one began
    /// (FramePacer.h).
    void waitForNextFrame() { m_pacer.waitForNextFrame(); }

    /// Both at full detail in the last frame.
    bool reached() const { return !m_heights.is_null() && !m_imagery.is_null(); }
    double seconds() const;
    /// {"frames", "seconds", "heights": {"frames", "seconds"}, "imagery": {…}} once
    /// reached(), else null.
    nlohmann::json result() const;

private:
    using Clock = std::chrono::steady_clock;
    Clock::time_point m_arrived;
    FramePacer m_pacer{kArrivalFrameS};
    std::uint64_t m_frames = 0;
    nlohmann::json m_heights, m_imagery;  // null while not at full detail
};

}  // namespace terrain::tools
