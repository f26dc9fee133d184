// PathRecorder: turns a flight into a camera path file (docs/camera-path.md), the same
// formats terrain-render and the viewer's --path play: the camera every kIntervalS of
// flight time (a yaw/pitch keyframe on the plane, a pose on the globe:
// FlightPath::fromCameras), which the path's spline passes through exactly.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/FlightPath.h"

#include <cstddef>
#include <vector>

namespace terrain::view {

/// Render thread only.
class PathRecorder {
public:
    /// Four keyframes a second: a spline through them follows a hand-flown camera closely
    /// while the file stays small (about 100 bytes a keyframe).
    static constexpr double kIntervalS = 0.25;

    /// Starts a new recording (dropping an unfinished one) of a path over `frame`'s surface
    /// with the camera at `timeS` as its first keyframe, at path time 0.
    void start(runtime::PathFrame frame, double timeS, const runtime::Camera& camera);
    /// Adds a keyframe when kIntervalS has passed since the previous one.
    void sample(double timeS, const runtime::Camera& camera);
    /// Adds the camera at `timeS` as the last keyframe (unless it is within a millisecond of
    /// the previous one) and returns the path; recording() is false afterwards, and the
    /// counts below are the finished path's until the next start().
    Result<runtime::FlightPath> finish(double timeS, const runtime::Camera& camera);

    bool recording() const { return m_recording; }
    std::size_t keyframeCount() const { return m_samples.size(); }
    /// Path time of the newest keyframe, seconds.
    double recordedS() const { return m_samples.empty() ? 0.0 : m_samples.back().timeS; }

private:
    void add(double timeS, const runtime::Camera& camera);

    runtime::PathFrame m_frame = runtime::PathFrame::Plane;
    std::vector<runtime::CameraSample> m_samples;
    double m_startS = 0.0;
    bool m_recording = false;
};

}  // namespace terrain::view
