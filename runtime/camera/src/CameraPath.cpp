// CameraPath: checking, Hermite/Catmull–Rom playback, the JSON file of
// docs/camera-path.md and the default flight over a pyramid.
#include "terrain/runtime/CameraPath.h"

#include "PathChecks.h"
#include "PathJson.h"
#include "PathSpline.h"
#include "terrain/runtime/FlightPath.h"

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <span>
#include <string>
#include <string_view>
#include <utility>

namespace terrain::runtime {
namespace {

using path_json::FileProblem;
using path_json::Json;
using path_json::numberAt;
using path_json::rejectUnknownKeys;
using path_spline::catmullRomTangent;
using path_spline::hermite;

double degrees(double radians) { return radians * (180.0 / std::numbers::pi); }
double radians(double degreesValue) { return degreesValue * (std::numbers::pi / 180.0); }

bool finite(const glm::dvec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// Yaw and pitch of the direction from `from` to `to`, exactly as Camera::lookAt sets them.
std::pair<double, double> yawPitchToward(const glm::dvec3& from, const glm::dvec3& to) {
    Camera camera;
    camera.position = from;
    camera.lookAt(to);
    return {camera.yaw, camera.pitch};
}

// What is wrong with the keyframes, in the JSON file's key names, or nothing.
std::optional<std::string> problemWith(const std::vector<CameraKeyframe>& keyframes) {
    if (keyframes.empty()) return std::string(path_checks::kEmpty);
    for (std::size_t i = 0; i < keyframes.size(); ++i) {
        const CameraKeyframe& k = keyframes[i];
        if (auto problem = path_checks::timeProblem(keyframes, i)) return problem;
        if (!finite(k.position))
            return fmt::format("keyframes[{}].position_m ({}, {}, {}) must be finite", i,
                               k.position.x, k.position.y, k.position.z);
        if (k.lookAt) {
            if (!finite(*k.lookAt))
                return fmt::format("keyframes[{}].look_at_m ({}, {}, {}) must be finite", i,
                                   k.lookAt->x, k.lookAt->y, k.lookAt->z);
            if (*k.lookAt == k.position)
                return fmt::format(
                    "keyframes[{}].look_at_m equals position_m; the camera cannot look at "
                    "its own position",
                    i);
        } else {
            if (!std::isfinite(k.yaw))
                return fmt::format("keyframes[{}].yaw_deg is {}; it must be finite", i,
                                   degrees(k.yaw));
            if (!(std::abs(k.pitch) <= 0.5 * std::numbers::pi))
                return fmt::format(
                    "keyframes[{}].pitch_deg is {}; it must lie within -90 … 90 degrees", i,
                    degrees(k.pitch));
        }
        if (auto problem = path_checks::fovProblem(i, k.fovYDegrees)) return problem;
    }
    return std::nullopt;
}

// ---- JSON reading: a problem is thrown as text and prefixed with the path at the top. --

glm::dvec3 vectorAt(const Json& object, std::string_view key, const std::string& where) {
    const auto it = object.find(key);
    if (it == object.end())
        throw FileProblem{
            fmt::format("{}missing \"{}\" (an array [x, y, z] of numbers)", where, key)};
    const Json& v = *it;
    if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() ||
        !v[2].is_number())
        throw FileProblem{fmt::format("{}\"{}\" must be an array [x, y, z] of 3 numbers, not {}",
                                      where, key, v.dump())};
    return {v[0].get<double>(), v[1].get<double>(), v[2].get<double>()};
}

CameraKeyframe keyframeFromJson(const Json& j, std::size_t index) {
    const std::string where = path_json::checkedKeyframe(j, index);
    rejectUnknownKeys(j, path_json::pathFormat(PathFrame::Plane).keyframeKeys, where);
    CameraKeyframe k;
    k.timeS = numberAt(j, "time_s", where);
    k.position = vectorAt(j, "position_m", where);
    const bool hasLookAt = j.contains("look_at_m");
    const bool hasYaw = j.contains("yaw_deg");
    const bool hasPitch = j.contains("pitch_deg");
    if (hasLookAt && (hasYaw || hasPitch))
        throw FileProblem{fmt::format(
            "{}give either \"look_at_m\" or \"yaw_deg\" and \"pitch_deg\", not both", where)};
    if (hasLookAt) {
        k.lookAt = vectorAt(j, "look_at_m", where);
    } else if (hasYaw || hasPitch) {
        k.yaw = radians(numberAt(j, "yaw_deg", where));
        k.pitch = radians(numberAt(j, "pitch_deg", where));
    } else {
        throw FileProblem{fmt::format(
            "{}missing the view: give \"look_at_m\" or \"yaw_deg\" and \"pitch_deg\"", where)};
    }
    k.fovYDegrees = numberAt(j, "fov_y_deg", where);
    return k;
}

Json keyframeToJson(const CameraKeyframe& k) {
    Json j;
    j["time_s"] = k.timeS;
    j["position_m"] = {k.position.x, k.position.y, k.position.z};
    if (k.lookAt) {
        j["look_at_m"] = {k.lookAt->x, k.lookAt->y, k.lookAt->z};
    } else {
        j["yaw_deg"] = degrees(k.yaw);
        j["pitch_deg"] = degrees(k.pitch);
    }
    j["fov_y_deg"] = k.fovYDegrees;
    return j;
}

// ---- The default path ----------------------------------------------------------------

// Where a ray from `from` (inside the box) along `direction` leaves the box [lo, hi]².
double exitDistance(glm::dvec2 from, glm::dvec2 direction, double lo, double hi) {
    double distance = std::numeric_limits<double>::infinity();
    for (int axis = 0; axis < 2; ++axis) {
        if (direction[axis] > 0.0)
            distance = std::min(distance, (hi - from[axis]) / direction[axis]);
        if (direction[axis] < 0.0)
            distance = std::min(distance, (lo - from[axis]) / direction[axis]);
    }
    return distance;
}

}  // namespace

std::vector<CameraKeyframe> path_json::planarKeyframes(const Json& list) {
    std::vector<CameraKeyframe> keyframes;
    keyframes.reserve(list.size());
    for (std::size_t i = 0; i < list.size(); ++i) keyframes.push_back(keyframeFromJson(list[i], i));
    return keyframes;
}

CameraPath::CameraPath(std::vector<CameraKeyframe> keyframes) : m_keyframes(std::move(keyframes)) {
    const std::size_t n = m_keyframes.size();
    std::vector<double> times(n);
    std::vector<glm::dvec3> positions(n);
    std::vector<glm::dvec3> targets(n);
    m_yaw.resize(n);
    m_pitch.resize(n);
    m_tangents.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const CameraKeyframe& k = m_keyframes[i];
        times[i] = k.timeS;
        positions[i] = k.position;
        targets[i] = k.lookAt.value_or(k.position);
        const auto [yaw, pitch] =
            k.lookAt ? yawPitchToward(k.position, *k.lookAt) : std::pair{k.yaw, k.pitch};
        // Unwrapped: each yaw lies within π of the one before, so the spline turns the
        // short way (350° → 10° is a 20° turn).
        m_yaw[i] = i == 0
                       ? std::remainder(yaw, 2.0 * std::numbers::pi)
                       : m_yaw[i - 1] + std::remainder(yaw - m_yaw[i - 1], 2.0 * std::numbers::pi);
        m_pitch[i] = pitch;
    }
    for (std::size_t i = 0; i < n; ++i) {
        Tangents& t = m_tangents[i];
        const bool hasPrevious = i > 0;
        const bool hasNext = i + 1 < n;
        t.position = catmullRomTangent<glm::dvec3>(positions, times, i, hasPrevious, hasNext);
        t.yaw = catmullRomTangent<double>(m_yaw, times, i, hasPrevious, hasNext);
        t.pitch = catmullRomTangent<double>(m_pitch, times, i, hasPrevious, hasNext);
        if (m_keyframes[i].lookAt) {
            // Targets are splined over the run of consecutive look-at keyframes only.
            t.lookAt = catmullRomTangent<glm::dvec3>(targets, times, i,
                                                     hasPrevious && m_keyframes[i - 1].lookAt,
                                                     hasNext && m_keyframes[i + 1].lookAt);
        }
    }
}

std::optional<std::size_t> CameraPath::firstOverflowingKeyframe() const {
    for (std::size_t i = 0; i < m_tangents.size(); ++i) {
        const Tangents& t = m_tangents[i];
        if (!finite(t.position) || !finite(t.lookAt) || !std::isfinite(t.yaw) ||
            !std::isfinite(t.pitch))
            return i;
    }
    return std::nullopt;
}

Result<CameraPath> CameraPath::checked(std::vector<CameraKeyframe> keyframes,
                                       const std::string& sourceName) {
    if (std::optional<std::string> problem = problemWith(keyframes))
        return Error{fmt::format("{}: {}", sourceName, *problem)};
    CameraPath path(std::move(keyframes));
    if (std::optional<std::size_t> i = path.firstOverflowingKeyframe())
        return Error{path_checks::overflowProblem(sourceName, *i)};
    return path;
}

Result<CameraPath> CameraPath::fromKeyframes(std::vector<CameraKeyframe> keyframes) {
    return checked(std::move(keyframes), "camera path");
}

Result<CameraPath> CameraPath::load(const std::filesystem::path& path) {
    Result<FlightPath> loaded = FlightPath::load(path, PathFrame::Plane);
    if (!loaded) return loaded.error();
    return *loaded.value().planar();
}

Status CameraPath::save(const std::filesystem::path& path) const {
    std::vector<Json> keyframes;
    for (const CameraKeyframe& k : m_keyframes) keyframes.push_back(keyframeToJson(k));
    return path_json::writeFile(path, path_json::pathFormat(PathFrame::Plane), keyframes);
}

void CameraPath::apply(double timeS, Camera& camera) const {
    const std::size_t n = m_keyframes.size();
    double t = timeS;
    if (!(t > startS())) t = startS();  // also catches NaN
    if (t > endS()) t = endS();

    // The segment [i, i + 1] holding t; a single keyframe is a segment of itself.
    std::size_t i = 0;
    if (n > 1) {
        const auto after =
            std::upper_bound(m_keyframes.begin(), m_keyframes.end(), t,
                             [](double value, const CameraKeyframe& k) { return value < k.timeS; });
        i = std::min(static_cast<std::size_t>(after - m_keyframes.begin()) - 1, n - 2);
    }
    const std::size_t j = std::min(i + 1, n - 1);
    const CameraKeyframe& a = m_keyframes[i];
    const CameraKeyframe& b = m_keyframes[j];
    const double dt = b.timeS - a.timeS;
    const double s = dt > 0.0 ? (t - a.timeS) / dt : 0.0;

    camera.position =
        hermite(a.position, m_tangents[i].position, b.position, m_tangents[j].position, dt, s);
    if (a.lookAt && b.lookAt) {
        camera.lookAt(
            hermite(*a.lookAt, m_tangents[i].lookAt, *b.lookAt, m_tangents[j].lookAt, dt, s));
    } else {
        const double yaw = hermite(m_yaw[i], m_tangents[i].yaw, m_yaw[j], m_tangents[j].yaw, dt, s);
        const double pitch =
            hermite(m_pitch[i], m_tangents[i].pitch, m_pitch[j], m_tangents[j].pitch, dt, s);
        camera.yaw = std::remainder(yaw, 2.0 * std::numbers::pi);
        camera.pitch = std::clamp(pitch, -Camera::kMaxPitch, Camera::kMaxPitch);
    }
    // Smoothstep: C1 at the keyframes and never outside [a, b], so never outside (0, 180).
    const double ease = s * s * (3.0 - 2.0 * s);
    camera.fovY = radians(a.fovYDegrees + (b.fovYDegrees - a.fovYDegrees) * ease);
}

CameraPath CameraPath::defaultFor(const TerrainGeometry& geometry, double durationS) {
    TERRAIN_ASSERT(std::isfinite(durationS) && durationS > 0.0,
                   "CameraPath::defaultFor needs a positive duration");
    const glm::dvec2 size = geometry.demSize();
    const glm::dvec2 spacing = geometry.sampleSpacing();
    const double low = std::min(geometry.minHeight(), geometry.maxHeight());
    const double high = std::max(geometry.minHeight(), geometry.maxHeight());
    TERRAIN_ASSERT(size.x > 0.0 && size.y > 0.0 && std::isfinite(low) && std::isfinite(high),
                   "CameraPath::defaultFor needs a DEM with an extent and finite heights");

    // The flight is laid out in a frame u (east), n (north) ∈ [0, 1]² centred on the DEM.
    // The frame is the DEM stretched by at most 2:1, so turns keep their shape on long,
    // narrow DEMs (which it then leaves partly unvisited) instead of flattening out.
    const glm::dvec2 centre = geometry.worldAtFraction(0.5, 0.5);
    const glm::dvec2 frame{std::min(size.x, 2.0 * size.y), std::min(size.y, 2.0 * size.x)};
    const auto world = [&](glm::dvec2 un) { return centre + (un - 0.5) * frame; };

    // Ground heights below the path are unknown here, so "low" is above the highest point.
    const double clearance = std::max(50.0, 20.0 * std::max(spacing.x, spacing.y));
    const double lowZ = high + clearance;
    // Wide view: 55° down at distance 0.6·extent / tan(fov/2), which fits the whole DEM
    // in the vertical field of view; further when the relief would put that below lowZ.
    const double fovY = radians(kDefaultFovYDegrees);
    const double widePitch = radians(55.0);
    const double wideDistance = std::max(0.6 * std::max(size.x, size.y) / std::tan(0.5 * fovY),
                                         (lowZ + 2.0 * clearance - low) / std::sin(widePitch));
    const double highZ = low + wideDistance * std::sin(widePitch);
    const double wideRadius = wideDistance * std::cos(widePitch);
    // The climb from lowZ to highZ over keyframes 0 … 5 grows 4× per segment. Spline
    // tangents of a sequence growing at most 5× never undershoot (Fritsch & Carlson 1980,
    // monotonicity region), so the camera never sinks below lowZ.
    const auto climbZ = [&](int k) {
        return lowZ + (highZ - lowZ) * (std::pow(4.0, k) - 1.0) / (std::pow(4.0, 5) - 1.0);
    };
    // Look ahead 15° down, no further than the frame's inner box allows.
    const double lookDown = std::tan(radians(15.0));

    std::vector<CameraKeyframe> keyframes;
    const auto add = [&](glm::dvec2 xy, double z, glm::dvec2 target) {
        const double t = durationS * static_cast<double>(keyframes.size()) / 7.0;
        keyframes.push_back({.timeS = t,
                             .position = {xy, z},
                             .lookAt = glm::dvec3(target, low),
                             .fovYDegrees = kDefaultFovYDegrees});
    };
    // (a) Low pass from the south-west, heading east-north-east, then (b) the climb turning
    // left toward the centre. Angles are headings in the frame, counter-clockwise from east.
    struct Ahead {
        glm::dvec2 un;
        double headingDeg;
    };
    constexpr std::array<Ahead, 4> kAhead = {
        {{{0.12, 0.15}, 20.0}, {{0.38, 0.20}, 25.0}, {{0.62, 0.28}, 45.0}, {{0.80, 0.42}, 120.0}}};
    for (int k = 0; k < 4; ++k) {
        const Ahead& a = kAhead[static_cast<std::size_t>(k)];
        const double z = climbZ(k);
        const glm::dvec2 heading{std::cos(radians(a.headingDeg)), std::sin(radians(a.headingDeg))};
        const glm::dvec2 far = a.un + exitDistance(a.un, heading, 0.05, 0.95) * heading;
        const glm::dvec2 from = world(a.un);
        const glm::dvec2 toFar = world(far) - from;
        const double gap = std::min((z - low) / lookDown, glm::length(toFar));
        add(from, z, from + gap * glm::normalize(toFar));
    }
    // The end of the climb looks at the centre no steeper than the wide view does: on a
    // DEM much higher than wide (or much longer than broad) it moves outward with its
    // height instead of hanging above the centre, which also keeps the step to the wide
    // view from dwarfing the steps before it (Catmull–Rom swings wide after a short step
    // followed by a long one).
    const glm::dvec2 climbOffset = world({0.85, 0.55}) - centre;
    const double climbRadius =
        std::max(glm::length(climbOffset), (climbZ(4) - low) / std::tan(widePitch));
    add(centre + climbRadius * glm::normalize(climbOffset), climbZ(4), centre);
    // (c) Wide view, orbiting counter-clockwise from the east-north-east to the north.
    for (const double azimuthDeg : {30.0, 60.0, 90.0}) {
        const glm::dvec2 offset{std::cos(radians(azimuthDeg)), std::sin(radians(azimuthDeg))};
        add(centre + wideRadius * offset, highZ, centre);
    }
    Result<CameraPath> path = fromKeyframes(std::move(keyframes));
    TERRAIN_ASSERT(path.ok(), "CameraPath::defaultFor built an invalid path");
    return std::move(path).value();
}

}  // namespace terrain::runtime
