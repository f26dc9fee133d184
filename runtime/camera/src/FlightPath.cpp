// FlightPath: the one camera path reader (either format, or one surface's), the writer and
// the player of both surfaces' paths.
#include "terrain/runtime/FlightPath.h"

#include "PathJson.h"
#include "terrain/runtime/GlobeCamera.h"

#include <fmt/format.h>

#include <numbers>
#include <utility>
#include <vector>

namespace terrain::runtime {

std::string_view pathFrameName(PathFrame frame) {
    return frame == PathFrame::Globe ? "globe" : "planar";
}

FlightPath::FlightPath(CameraPath path)
    : m_planar(std::make_shared<const CameraPath>(std::move(path))) {}

FlightPath::FlightPath(GlobeCameraPath path)
    : m_globe(std::make_shared<const GlobeCameraPath>(std::move(path))) {}

Result<FlightPath> FlightPath::load(const std::filesystem::path& file) {
    return read(file, nullptr);
}

Result<FlightPath> FlightPath::load(const std::filesystem::path& file, PathFrame frame) {
    return read(file, &frame);
}

Result<FlightPath> FlightPath::read(const std::filesystem::path& file,
                                    const PathFrame* insistedFrame) {
    using path_json::FileProblem;
    Result<path_json::Json> root = path_json::readFile(file);
    if (!root) return root.error();
    const PathFrame frame =
        insistedFrame != nullptr ? *insistedFrame
        : path_json::formatIs(root.value(), path_json::pathFormat(PathFrame::Globe).name)
            ? PathFrame::Globe
            : PathFrame::Plane;
    const path_json::PathFormat& other =
        path_json::pathFormat(frame == PathFrame::Plane ? PathFrame::Globe : PathFrame::Plane);
    const std::string name = file.string();
    try {
        // The other surface's file is refused by what it is, not by its first wrong key.
        if (path_json::formatIs(root.value(), other.name))
            throw FileProblem{std::string(other.forOtherSurface)};
        const path_json::Json& list =
            path_json::checkedKeyframes(root.value(), path_json::pathFormat(frame));
        if (frame == PathFrame::Plane) {
            Result<CameraPath> path = CameraPath::checked(path_json::planarKeyframes(list), name);
            if (!path) return path.error();
            return FlightPath(std::move(path).value());
        }
        Result<GlobeCameraPath> path =
            GlobeCameraPath::checked(path_json::globeKeyframes(list), name);
        if (!path) return path.error();
        return FlightPath(std::move(path).value());
    } catch (const FileProblem& problem) {
        return Error{fmt::format("{}: {}", name, problem.message)};
    }
}

Result<FlightPath> FlightPath::fromCameras(PathFrame frame, std::span<const CameraSample> samples) {
    const auto degrees = [](double radians) { return radians * (180.0 / std::numbers::pi); };
    if (frame == PathFrame::Plane) {
        std::vector<CameraKeyframe> keyframes;
        keyframes.reserve(samples.size());
        for (const CameraSample& s : samples)
            keyframes.push_back({.timeS = s.timeS,
                                 .position = s.camera.position,
                                 .lookAt = std::nullopt,
                                 .yaw = s.camera.yaw,
                                 .pitch = s.camera.pitch,
                                 .fovYDegrees = degrees(s.camera.fovY)});
        Result<CameraPath> path = CameraPath::fromKeyframes(std::move(keyframes));
        if (!path) return path.error();
        return FlightPath(std::move(path).value());
    }
    std::vector<GlobeKeyframe> keyframes;
    keyframes.reserve(samples.size());
    for (const CameraSample& s : samples)
        keyframes.push_back({.timeS = s.timeS,
                             .pose = globePoseOf(s.camera),
                             .fovYDegrees = degrees(s.camera.fovY)});
    Result<GlobeCameraPath> path = GlobeCameraPath::fromKeyframes(std::move(keyframes));
    if (!path) return path.error();
    return FlightPath(std::move(path).value());
}

Status FlightPath::save(const std::filesystem::path& file) const {
    return m_planar ? m_planar->save(file) : m_globe->save(file);
}

void FlightPath::apply(double timeS, Camera& camera) const {
    if (m_planar)
        m_planar->apply(timeS, camera);
    else
        m_globe->apply(timeS, camera);
}

}  // namespace terrain::runtime
