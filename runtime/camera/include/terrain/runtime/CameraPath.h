// CameraPath: keyframes (time, position, look-at target or yaw/pitch, field of view)
// played back as a smooth camera flight, read from and written to the JSON file of
// docs/camera-path.md, and a default path for any pyramid so every tool can fly without
// a hand-made file.
//
// Interpolation (docs/camera-path.md, "Playback"): every channel is a cubic Hermite
// spline in time with Catmull–Rom tangents m_i = (P_{i+1} − P_{i−1}) / (t_{i+1} − t_{i−1}),
// the end points duplicated, each tangent shortened to at most 3× the slower neighbouring
// chord speed (Fritsch & Carlson 1980) so the camera never swings back after a short
// step. For evenly spaced keyframes this is the uniform Catmull–Rom spline; for uneven
// spacing it keeps the velocity, not just the direction of travel, continuous at the
// keyframes. Positions use it; between two look-at keyframes the target uses it too and
// the camera looks from position to target; any other segment splines yaw (unwrapped to
// the shorter turn between neighbouring keyframes) and pitch. The field of view eases
// with smoothstep, so it never leaves the range of its two keyframes.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/TerrainGeometry.h"

#include <glm/vec3.hpp>

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace terrain::runtime {

struct CameraKeyframe {
    double timeS = 0.0;
    glm::dvec3 position{0.0};  ///< world metres: x east, y north, z up
    /// The world point to look at; when set, yaw and pitch are ignored, when empty they say
    /// where the camera looks.
    std::optional<glm::dvec3> lookAt;
    double yaw = 0.0;    ///< radians, Camera's convention: 0 looks north (+y), π/2 east (+x)
    double pitch = 0.0;  ///< radians, positive looks up, within ±π/2
    double fovYDegrees = 60.0;  ///< vertical field of view, in (0, 180)
};

/// An immutable, checked list of keyframes and its precomputed spline tangents. Loading
/// and saving touch only the named file; apply() is const, allocates nothing and may run
/// on any thread concurrently.
class CameraPath {
public:
    static constexpr double kDefaultFovYDegrees = 60.0;

    /// Checks the keyframes: at least one, finite values, times strictly increasing,
    /// |pitch| ≤ π/2, fov in (0, 180) degrees, a look-at target apart from its position,
    /// and no two keyframes so far apart for their times that the spline's speeds overflow.
    /// Errors start with "camera path: " and name the keyframe and key as the JSON file
    /// would (e.g. "keyframes[2].fov_y_deg").
    static Result<CameraPath> fromKeyframes(std::vector<CameraKeyframe> keyframes);

    /// Reads a camera path file (docs/camera-path.md) through the one reader,
    /// FlightPath::load(path, PathFrame::Plane). Errors start with the path and say what is
    /// wrong: a missing file, bad JSON, a missing, unknown or mistyped key (with the keyframe
    /// index), a value fromKeyframes rejects, or a globe camera path.
    static Result<CameraPath> load(const std::filesystem::path& path);

    /// Writes the file atomically (AtomicFile), numbers in the shortest form that reads
    /// back to the same double (angles go through degrees, so they round-trip to ~1e-15).
    Status save(const std::filesystem::path& path) const;

    /// A flight for any pyramid, from its extent and height range only: a low pass just
    /// above maxHeight looking ahead and down, a climb turning toward the DEM's centre, and
    /// a slowly orbiting wide view that fits the whole DEM. Every view ray meets the plane
    /// z = minHeight inside the DEM. Times run from 0 to durationS (> 0).
    static CameraPath defaultFor(const TerrainGeometry& geometry, double durationS = 20.0);

    double startS() const { return m_keyframes.front().timeS; }
    double endS() const { return m_keyframes.back().timeS; }
    /// endS() − startS(); 0 for a single keyframe.
    double durationS() const { return endS() - startS(); }
    const std::vector<CameraKeyframe>& keyframes() const { return m_keyframes; }

    /// Sets camera.position, yaw (wrapped to [−π, π]), pitch (clamped to ±kMaxPitch) and
    /// fovY at timeS, clamped to [startS(), endS()] (NaN plays startS()). Leaves the
    /// viewport and near plane alone. Deterministic; allocates nothing.
    void apply(double timeS, Camera& camera) const;

private:
    friend class FlightPath;  // its reader checks keyframes under the file's name (checked)
    // Hermite tangents per keyframe, in units per second.
    struct Tangents {
        glm::dvec3 position{0.0};
        glm::dvec3 lookAt{0.0};  ///< over the run of look-at keyframes this one belongs to
        double yaw = 0.0;
        double pitch = 0.0;
    };

    explicit CameraPath(std::vector<CameraKeyframe> keyframes);
    /// fromKeyframes and load: checks, builds, and checks the tangents are finite. Errors
    /// start with `sourceName`.
    static Result<CameraPath> checked(std::vector<CameraKeyframe> keyframes,
                                      const std::string& sourceName);
    std::optional<std::size_t> firstOverflowingKeyframe() const;

    std::vector<CameraKeyframe> m_keyframes;
    std::vector<double> m_yaw;    ///< per keyframe, unwrapped: neighbours differ by ≤ π
    std::vector<double> m_pitch;  ///< per keyframe (look-at keyframes converted)
    std::vector<Tangents> m_tangents;
};

}  // namespace terrain::runtime
