// PathRecorder: turns a flight into a camera path file (docs/camera-path.md), the same
// format terrain-render and the viewer's --path play: a yaw/pitch keyframe every
// kIntervalS of flight time, which the path's Catmull–Rom spline passes through exactly.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/CameraPath.h"

#include <cstddef>
#include <vector>

namespace terrain::view {

/// Render thread only.
class PathRecorder {
public:
    /// Four keyframes a second: a spline through them follows a hand-flown camera closely
    /// while the file stays small (about 100 bytes a keyframe).
    static constexpr double kIntervalS = 0.25;

    /// Starts a new recording (dropping an unfinished one) with the camera at `timeS` as its
    /// first keyframe, at path time 0.
    void start(double timeS, const runtime::Camera& camera);
    /// Adds a keyframe when kIntervalS has passed since the previous one.
    void sample(double timeS, const runtime::Camera& camera);
    /// Adds the camera at `timeS` as the last keyframe (unless it is within a millisecond of
    /// the previous one) and returns the path; recording() is false afterwards.
    Result<runtime::CameraPath> finish(double timeS, const runtime::Camera& camera);

    bool recording() const { return m_recording; }
    std::size_t keyframeCount() const { return m_keyframes.size(); }
    /// Path time of the newest keyframe, seconds.
    double recordedS() const { return m_keyframes.empty() ? 0.0 : m_keyframes.back().timeS; }

private:
    void add(double timeS, const runtime::Camera& camera);

    std::vector<runtime::CameraKeyframe> m_keyframes;
    double m_startS = 0.0;
    bool m_recording = false;
};

}  // namespace terrain::view
