// Camera keyframes sampled during a flight.
#include "PathRecorder.h"

#include <numbers>
#include <utility>

namespace terrain::view {
namespace {

constexpr double kMinKeyframeGapS = 1e-3;

double degrees(double radians) { return radians * 180.0 / std::numbers::pi; }

}  // namespace

void PathRecorder::start(double timeS, const runtime::Camera& camera) {
    m_keyframes.clear();
    m_startS = timeS;
    m_recording = true;
    add(timeS, camera);
}

void PathRecorder::sample(double timeS, const runtime::Camera& camera) {
    if (!m_recording) return;
    if (timeS - m_startS - recordedS() >= kIntervalS) add(timeS, camera);
}

Result<runtime::CameraPath> PathRecorder::finish(double timeS, const runtime::Camera& camera) {
    m_recording = false;
    if (m_keyframes.empty() || timeS - m_startS - recordedS() >= kMinKeyframeGapS) {
        add(timeS, camera);
    }
    return runtime::CameraPath::fromKeyframes(std::exchange(m_keyframes, {}));
}

void PathRecorder::add(double timeS, const runtime::Camera& camera) {
    runtime::CameraKeyframe keyframe;
    keyframe.timeS = timeS - m_startS;
    keyframe.position = camera.position;
    keyframe.yaw = camera.yaw;
    keyframe.pitch = camera.pitch;
    keyframe.fovYDegrees = degrees(camera.fovY);
    m_keyframes.push_back(keyframe);
}

}  // namespace terrain::view
