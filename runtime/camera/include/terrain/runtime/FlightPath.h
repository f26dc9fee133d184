// FlightPath: a camera flight on either surface, a planar CameraPath (world metres) or a
// GlobeCameraPath (latitude, longitude, height), behind one reader, writer and player
// (docs/camera-path.md, "One reader"). A program that flies both surfaces holds this; the
// file's "format" says which path it is, and a pyramid's surface may insist on its own.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/CameraPath.h"
#include "terrain/runtime/GlobeCameraPath.h"

#include <filesystem>
#include <memory>
#include <span>
#include <string_view>

namespace terrain::runtime {

/// The surface a camera path's keyframes are written for.
enum class PathFrame { Plane, Globe };

/// "planar" or "globe", as the errors and reports say it.
std::string_view pathFrameName(PathFrame frame);

/// A camera where a flight was at a time, for fromCameras.
struct CameraSample {
    double timeS = 0.0;
    Camera camera;
};

/// Immutable; apply() is const, allocates nothing and may run on any thread concurrently
/// (copies share the path).
class FlightPath {
public:
    FlightPath(CameraPath path);       // NOLINT: a planar path is a flight path
    FlightPath(GlobeCameraPath path);  // NOLINT: so is a globe one

    /// Reads a camera path file of either format, as its "format" says (a file without a
    /// recognised one is read, and refused, as a planar path). Errors start with the file.
    static Result<FlightPath> load(const std::filesystem::path& file);
    /// Reads a camera path file for a pyramid of `frame`'s surface: the other surface's
    /// format is refused by name (e.g. "a globe camera path (…); a planar pyramid flies a
    /// \"terrain-camera-path\" …"). Errors start with the file.
    static Result<FlightPath> load(const std::filesystem::path& file, PathFrame frame);

    /// A path through `samples` (times increasing): on the plane a yaw/pitch keyframe per
    /// sample (position, yaw, pitch, field of view), on the globe the sample's pose
    /// (globePoseOf) and field of view. The spline passes through every sample. Errors as
    /// CameraPath::fromKeyframes and GlobeCameraPath::fromKeyframes give them.
    static Result<FlightPath> fromCameras(PathFrame frame, std::span<const CameraSample> samples);

    /// Writes the file of the path's own format atomically.
    Status save(const std::filesystem::path& file) const;

    PathFrame frame() const { return m_planar ? PathFrame::Plane : PathFrame::Globe; }
    /// The planar path, or null on a globe; the globe path, or null on a plane.
    const CameraPath* planar() const { return m_planar.get(); }
    const GlobeCameraPath* globe() const { return m_globe.get(); }

    double startS() const { return m_planar ? m_planar->startS() : m_globe->startS(); }
    double endS() const { return m_planar ? m_planar->endS() : m_globe->endS(); }
    double durationS() const { return endS() - startS(); }

    /// The camera at `timeS` (clamped to the path), as the held path's apply() sets it.
    void apply(double timeS, Camera& camera) const;

private:
    static Result<FlightPath> read(const std::filesystem::path& file,
                                   const PathFrame* insistedFrame);

    // One of the two is set. Held through shared_ptr rather than a std::variant, on which
    // GCC 12 warns "maybe-uninitialized" falsely in Release builds.
    std::shared_ptr<const CameraPath> m_planar;
    std::shared_ptr<const GlobeCameraPath> m_globe;
};

}  // namespace terrain::runtime
