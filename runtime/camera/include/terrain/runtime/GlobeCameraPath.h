// GlobeCameraPath: a camera flight over a globe pyramid in geodetic terms (docs/camera-path.md,
// "Globe camera paths"): keyframes of latitude, longitude, height above the WGS84 ellipsoid,
// heading, pitch and field of view, played back as one smooth flight, read from and written to
// a JSON file, and the default flight from orbit down to the data.
//
// Playback uses the planar path's spline (cubic Hermite, Catmull–Rom tangents shortened after
// Fritsch & Carlson 1980) on these channels: latitude, longitude unwrapped to the shorter way
// round (so 179° → −179° crosses the antimeridian, 2° of travel), asinh(height / 1 m), heading
// unwrapped, pitch. asinh makes a descent from orbit exponential (the same number of frames
// per halving of the height, from 20,000 km to 1 m) while staying linear and defined near and
// below 0 m (the Dead Sea). The field of view eases with smoothstep.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/GlobeCamera.h"

#include <cstddef>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace terrain::runtime {

struct GlobeKeyframe {
    double timeS = 0.0;
    GlobePose pose;  ///< latitude within ±90°, any longitude and heading, pitch within ±90°
    double fovYDegrees = 60.0;
};

/// A place the default flight visits: where, and the height it arrives at (the ground there
/// plus the clearance wanted).
struct GlobeTourStop {
    double latitudeDeg = 0.0;
    double longitudeDeg = 0.0;
    double endHeightM = 0.0;
};

/// An immutable, checked list of keyframes and its spline tangents; poseAt and apply are
/// const, allocate nothing and may run on any thread concurrently.
class GlobeCameraPath {
public:
    static constexpr double kDefaultFovYDegrees = 50.0;
    static constexpr double kOrbitHeightM = 20e6;

    /// Checks the keyframes: at least one, finite values, times strictly increasing, latitude
    /// and pitch within ±90°, heights within ±1e9 m, fov in (0, 180). Errors start with
    /// "globe camera path: " and name the key as the file would ("keyframes[2].height_m").
    static Result<GlobeCameraPath> fromKeyframes(std::vector<GlobeKeyframe> keyframes);

    /// Reads a globe camera path file through the one reader, FlightPath::load(path,
    /// PathFrame::Globe); errors start with the path and say what is wrong (a missing file,
    /// bad JSON, a missing, unknown or mistyped key, a value fromKeyframes rejects, or a
    /// planar camera path given for a globe).
    static Result<GlobeCameraPath> load(const std::filesystem::path& path);

    /// Writes the file atomically, one keyframe per line.
    Status save(const std::filesystem::path& path) const;

    /// The default flight over `latitudeDeg`, `longitudeDeg`: straight down from 20,000 km,
    /// the height falling exponentially to `endHeightM` (give the ground there plus the
    /// clearance wanted), tilting from −90° to −5° (the horizon in view from the ground) over
    /// the last 40 % of `durationS`.
    static GlobeCameraPath fromOrbit(double latitudeDeg, double longitudeDeg, double endHeightM,
                                     double durationS = 20.0);

    /// The default flight over several places in turn, each given durationS / n: from orbit
    /// down to the first as fromOrbit does, then to each next one up (straight up to a height
    /// as great as the distance between the two, so both are in view), across at that height
    /// and straight down as fromOrbit ends, tilting to the horizon. Every stop but the last is
    /// held for the last 15 % of its share, so its detail shows; the last is reached at the
    /// end. One stop: fromOrbit exactly. Asserts a stop and a positive duration.
    static GlobeCameraPath fromTour(std::span<const GlobeTourStop> stops, double durationS = 20.0);
    /// When fromTour(stops, durationS) arrives at stop `index` of `count`.
    static double tourArrivalS(std::size_t index, std::size_t count, double durationS);

    double startS() const { return m_keyframes.front().timeS; }
    double endS() const { return m_keyframes.back().timeS; }
    double durationS() const { return endS() - startS(); }
    const std::vector<GlobeKeyframe>& keyframes() const { return m_keyframes; }

    /// The pose at `timeS`, clamped to [startS(), endS()] (NaN plays startS()); latitude
    /// within ±90°, longitude and heading wrapped to [−180°, 180°].
    GlobePose poseAt(double timeS) const;
    double fovYDegreesAt(double timeS) const;
    /// placeOnGlobe(camera, poseAt(timeS)) and the field of view; leaves the viewport alone.
    void apply(double timeS, Camera& camera) const;

private:
    friend class FlightPath;  // its reader checks keyframes under the file's name (checked)
    enum Channel { kLatitude, kLongitude, kHeight, kHeading, kPitch, kChannels };
    explicit GlobeCameraPath(std::vector<GlobeKeyframe> keyframes);
    static Result<GlobeCameraPath> checked(std::vector<GlobeKeyframe> keyframes,
                                           const std::string& sourceName);
    /// The segment holding `timeS` (clamped) and the position in it, s ∈ [0, 1].
    struct Segment {
        std::size_t i = 0, j = 0;
        double dt = 0.0, s = 0.0;
    };
    Segment segmentAt(double timeS) const;

    std::vector<GlobeKeyframe> m_keyframes;
    std::vector<double> m_times;
    std::vector<double> m_values[kChannels];    ///< per channel, per keyframe (unwrapped)
    std::vector<double> m_tangents[kChannels];  ///< per channel, per keyframe, per second
};

}  // namespace terrain::runtime
