// FramePacer: frames at most as often as a display shows them. A program that draws frames
// as a user would see them (not waiting for streaming) waits out the rest of each frame's
// time: frames drawn faster than a display shows them (llvmpipe's small or empty frames take
// microseconds) would otherwise count waits for the I/O as frames a user never sees, and a
// cold start would race through a camera path before its first tile is in, drawing nothing.
#pragma once

#include <chrono>
#include <thread>

namespace terrain::tools {

class FramePacer {
public:
    /// Frames at least `frameS` seconds apart (> 0).
    explicit FramePacer(double frameS)
        : m_frame(
              std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(frameS))) {}

    /// Before each frame: waits until a frame's time has passed since the previous one
    /// began (the first does not wait).
    void waitForNextFrame() {
        std::this_thread::sleep_until(m_next);
        m_next = Clock::now() + m_frame;
    }

private:
    using Clock = std::chrono::steady_clock;
    Clock::duration m_frame;
    Clock::time_point m_next = Clock::now();
};

}  // namespace terrain::tools
