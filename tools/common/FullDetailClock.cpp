#include "FullDetailClock.h"

namespace terrain::tools {

namespace {

// Null when not at full detail; else kept from the frame it first was.
void track(nlohmann::json& since, bool full, std::uint64_t frame, double seconds) {
    if (!full)
        since = nullptr;
    else if (since.is_null())
        since = {{"frames", frame}, {"seconds", seconds}};
}

}  // namespace

void FullDetailClock::frameEnded(const runtime::LodStrategy& strategy,
                                 std::uint64_t waitingSplits) {
    ++m_frames;
    track(m_heights, waitingSplits == 0 && strategy.loadsOutstanding() == 0, m_frames, seconds());
    track(m_imagery, strategy.imageryWaiting() == 0, m_frames, seconds());
}

double FullDetailClock::seconds() const {
    return std::chrono::duration<double>(Clock::now() - m_arrived).count();
}

nlohmann::json FullDetailClock::result() const {
    if (!reached()) return nullptr;
    return {{"frames", m_frames},
            {"seconds", seconds()},
            {"heights", m_heights},
            {"imagery", m_imagery}};
}

}  // namespace terrain::tools
