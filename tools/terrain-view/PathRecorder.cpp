// Camera keyframes sampled during a flight.
#include "PathRecorder.h"


namespace terrain::view {
namespace {

constexpr double kMinKeyframeGapS = 1e-3;

}  // namespace

void PathRecorder::start(runtime::PathFrame frame, double timeS, const runtime::Camera& camera) {
    m_frame = frame;
    m_samples.clear();
    m_startS = timeS;
    m_recording = true;
    add(timeS, camera);
}

void PathRecorder::sample(double timeS, const runtime::Camera& camera) {
    if (!m_recording) return;
    if (timeS - m_startS - recordedS() >= kIntervalS) add(timeS, camera);
}

Result<runtime::FlightPath> PathRecorder::finish(double timeS, const runtime::Camera& camera) {
    m_recording = false;
    if (m_samples.empty() || timeS - m_startS - recordedS() >= kMinKeyframeGapS) {
        add(timeS, camera);
    }
    return runtime::FlightPath::fromCameras(m_frame, m_samples);
}

void PathRecorder::add(double timeS, const runtime::Camera& camera) {
    m_samples.push_back({timeS - m_startS, camera});
}

}  // namespace terrain::view
