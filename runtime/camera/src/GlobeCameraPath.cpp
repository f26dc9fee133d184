// GlobeCameraPath: checking, playback on the geodetic channels, the JSON file and the
// default flight from orbit.
#include "terrain/runtime/GlobeCameraPath.h"

#include "PathChecks.h"
#include "PathJson.h"
#include "PathSpline.h"
#include "terrain/runtime/FlightPath.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <optional>
#include <string_view>
#include <utility>

namespace terrain::runtime {
namespace {

using path_json::FileProblem;
using path_json::Json;

constexpr double kMaxAbsHeightM = 1e9;

double wrap180(double degrees) { return std::remainder(degrees, 360.0); }

std::optional<std::string> problemWith(const std::vector<GlobeKeyframe>& keyframes) {
    if (keyframes.empty()) return std::string(path_checks::kEmpty);
    for (std::size_t i = 0; i < keyframes.size(); ++i) {
        const GlobeKeyframe& k = keyframes[i];
        const GlobePose& p = k.pose;
        const auto bad = [&](std::string_view key, double value, std::string_view rule) {
            return fmt::format("keyframes[{}].{} is {}; {}", i, key, value, rule);
        };
        if (auto problem = path_checks::timeProblem(keyframes, i)) return problem;
        if (!(std::abs(p.where.latitudeDeg) <= 90.0))
            return bad("latitude_deg", p.where.latitudeDeg, "it must lie within -90 … 90");
        if (!std::isfinite(p.where.longitudeDeg))
            return bad("longitude_deg", p.where.longitudeDeg, "it must be finite");
        if (!(std::abs(p.where.height) <= kMaxAbsHeightM))
            return bad("height_m", p.where.height,
                       "it must lie within ±1e9 m of the ellipsoid (the Moon is 3.8e8 m away)");
        if (!std::isfinite(p.headingDeg))
            return bad("heading_deg", p.headingDeg, "it must be finite");
        if (!(std::abs(p.pitchDeg) <= 90.0))
            return bad("pitch_deg", p.pitchDeg, "it must lie within -90 … 90");
        if (auto problem = path_checks::fovProblem(i, k.fovYDegrees)) return problem;
    }
    return std::nullopt;
}

GlobeKeyframe globeKeyframeFromJson(const Json& j, std::size_t index) {
    const std::string where = path_json::checkedKeyframe(j, index);
    if (j.contains("position_m"))
        throw FileProblem{
            fmt::format("{}\"position_m\" is a planar camera path's key; a globe camera path gives "
                        "\"latitude_deg\", \"longitude_deg\" and \"height_m\"",
                        where)};
    path_json::rejectUnknownKeys(j, path_json::pathFormat(PathFrame::Globe).keyframeKeys, where);
    GlobeKeyframe k;
    k.timeS = path_json::numberAt(j, "time_s", where);
    k.pose.where.latitudeDeg = path_json::numberAt(j, "latitude_deg", where);
    k.pose.where.longitudeDeg = path_json::numberAt(j, "longitude_deg", where);
    k.pose.where.height = path_json::numberAt(j, "height_m", where);
    k.pose.headingDeg = path_json::numberAt(j, "heading_deg", where);
    k.pose.pitchDeg = path_json::numberAt(j, "pitch_deg", where);
    k.fovYDegrees = path_json::numberAt(j, "fov_y_deg", where);
    return k;
}

Json globeKeyframeToJson(const GlobeKeyframe& k) {
    Json j;
    j["time_s"] = k.timeS;
    j["latitude_deg"] = k.pose.where.latitudeDeg;
    j["longitude_deg"] = k.pose.where.longitudeDeg;
    j["height_m"] = k.pose.where.height;
    j["heading_deg"] = k.pose.headingDeg;
    j["pitch_deg"] = k.pose.pitchDeg;
    j["fov_y_deg"] = k.fovYDegrees;
    return j;
}

}  // namespace

std::vector<GlobeKeyframe> path_json::globeKeyframes(const Json& list) {
    std::vector<GlobeKeyframe> keyframes;
    keyframes.reserve(list.size());
    for (std::size_t i = 0; i < list.size(); ++i)
        keyframes.push_back(globeKeyframeFromJson(list[i], i));
    return keyframes;
}

GlobeCameraPath::GlobeCameraPath(std::vector<GlobeKeyframe> keyframes)
    : m_keyframes(std::move(keyframes)) {
    const std::size_t n = m_keyframes.size();
    m_times.resize(n);
    for (auto& channel : m_values) channel.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const GlobePose& p = m_keyframes[i].pose;
        m_times[i] = m_keyframes[i].timeS;
        m_values[kLatitude][i] = p.where.latitudeDeg;
        m_values[kHeight][i] = std::asinh(p.where.height);
        m_values[kPitch][i] = p.pitchDeg;
        // Unwrapped: each within 180° of the one before, so the path goes the short way round
        // (across the antimeridian) and turns the short way.
        for (const auto& [channel, value] :
             {std::pair{kLongitude, p.where.longitudeDeg}, std::pair{kHeading, p.headingDeg}}) {
            std::vector<double>& v = m_values[channel];
            v[i] = i == 0 ? wrap180(value) : v[i - 1] + wrap180(value - v[i - 1]);
        }
    }
    for (int c = 0; c < kChannels; ++c) {
        m_tangents[c].resize(n);
        for (std::size_t i = 0; i < n; ++i)
            m_tangents[c][i] =
                path_spline::catmullRomTangent<double>(m_values[c], m_times, i, i > 0, i + 1 < n);
    }
}

Result<GlobeCameraPath> GlobeCameraPath::checked(std::vector<GlobeKeyframe> keyframes,
                                                 const std::string& sourceName) {
    if (std::optional<std::string> problem = problemWith(keyframes))
        return Error{fmt::format("{}: {}", sourceName, *problem)};
    GlobeCameraPath path(std::move(keyframes));
    for (int c = 0; c < kChannels; ++c)
        for (std::size_t i = 0; i < path.m_tangents[c].size(); ++i)
            if (!std::isfinite(path.m_tangents[c][i]))
                return Error{path_checks::overflowProblem(sourceName, i)};
    return path;
}

Result<GlobeCameraPath> GlobeCameraPath::fromKeyframes(std::vector<GlobeKeyframe> keyframes) {
    return checked(std::move(keyframes), "globe camera path");
}

Result<GlobeCameraPath> GlobeCameraPath::load(const std::filesystem::path& path) {
    Result<FlightPath> loaded = FlightPath::load(path, PathFrame::Globe);
    if (!loaded) return loaded.error();
    return *loaded.value().globe();
}

Status GlobeCameraPath::save(const std::filesystem::path& path) const {
    std::vector<Json> keyframes;
    for (const GlobeKeyframe& k : m_keyframes) keyframes.push_back(globeKeyframeToJson(k));
    return path_json::writeFile(path, path_json::pathFormat(PathFrame::Globe), keyframes);
}

GlobeCameraPath GlobeCameraPath::fromOrbit(double latitudeDeg, double longitudeDeg,
                                           double endHeightM, double durationS) {
    TERRAIN_ASSERT(std::isfinite(durationS) && durationS > 0.0,
                   "GlobeCameraPath::fromOrbit needs a positive duration");
    // Straight down until 60 %, the height linear in asinh (exponential above a few metres)
    // throughout, then tilting toward the horizon.
    const double from = std::asinh(kOrbitHeightM), to = std::asinh(endHeightM);
    const auto keyframe = [&](double fraction, double pitchDeg) {
        return GlobeKeyframe{
            .timeS = fraction * durationS,
            .pose = {{latitudeDeg, longitudeDeg, std::sinh(from + (to - from) * fraction)},
                     0.0,
                     pitchDeg},
            .fovYDegrees = kDefaultFovYDegrees};
    };
    auto path = fromKeyframes({keyframe(0.0, -90.0), keyframe(0.6, -90.0), keyframe(1.0, -5.0)});
    TERRAIN_ASSERT(path.ok(), "GlobeCameraPath::fromOrbit built an invalid path");
    return std::move(path).value();
}

namespace {

// fromTour's share of each stop: the climb, the crossing and the hold end at these fractions of
// it; the descent fills what is left before the hold (fromOrbit's: straight down for 60 % of
// it, then tilting).
constexpr double kTourClimbEnds = 0.15, kTourCrossingEnds = 0.35, kTourHoldStarts = 0.85;
constexpr double kTourLowestHopM = 10e3;

// The distance between two places along the sphere of the ellipsoid's equatorial radius:
// what the height of the hop between them is made from (no more exact than that needs).
double roughDistanceM(const GlobeTourStop& a, const GlobeTourStop& b) {
    constexpr double kRadiansPerDegree = std::numbers::pi / 180.0, kRadiusM = 6378137.0;
    const double phi1 = a.latitudeDeg * kRadiansPerDegree;
    const double phi2 = b.latitudeDeg * kRadiansPerDegree;
    const double dPhi = phi2 - phi1;
    const double dLambda = (b.longitudeDeg - a.longitudeDeg) * kRadiansPerDegree;
    const double sinHalfPhi = std::sin(dPhi / 2), sinHalfLambda = std::sin(dLambda / 2);
    const double h =
        sinHalfPhi * sinHalfPhi + std::cos(phi1) * std::cos(phi2) * sinHalfLambda * sinHalfLambda;
    return 2.0 * kRadiusM * std::asin(std::min(1.0, std::sqrt(h)));  // haversine
}

}  // namespace

double GlobeCameraPath::tourArrivalS(std::size_t index, std::size_t count, double durationS) {
    const double share = durationS / double(count);
    return index + 1 == count ? durationS : (double(index) + kTourHoldStarts) * share;
}

GlobeCameraPath GlobeCameraPath::fromTour(std::span<const GlobeTourStop> stops, double durationS) {
    TERRAIN_ASSERT(!stops.empty(), "GlobeCameraPath::fromTour needs a stop");
    TERRAIN_ASSERT(std::isfinite(durationS) && durationS > 0.0,
                   "GlobeCameraPath::fromTour needs a positive duration");
    if (stops.size() == 1)
        return fromOrbit(stops[0].latitudeDeg, stops[0].longitudeDeg, stops[0].endHeightM,
                         durationS);
    const std::size_t n = stops.size();
    const double share = durationS / double(n);
    std::vector<GlobeKeyframe> keyframes;
    const auto add = [&](double timeS, const GlobeTourStop& at, double heightM, double pitchDeg) {
        keyframes.push_back({.timeS = timeS,
                             .pose = {{at.latitudeDeg, at.longitudeDeg, heightM}, 0.0, pitchDeg},
                             .fovYDegrees = kDefaultFovYDegrees});
    };
    // Straight down from `fromM` at `startS` to the stop at `arriveS`, height linear in asinh,
    // tilting over the last 40 %; then held until the next stop's share.
    const auto descend = [&](const GlobeTourStop& to, double fromM, double startS, double arriveS) {
        const double from = std::asinh(fromM), end = std::asinh(to.endHeightM);
        add(startS, to, fromM, -90.0);
        add(startS + 0.6 * (arriveS - startS), to, std::sinh(from + 0.6 * (end - from)), -90.0);
        add(arriveS, to, to.endHeightM, -5.0);
    };
    for (std::size_t i = 0; i < n; ++i) {
        const double startS = double(i) * share;
        const double arriveS = tourArrivalS(i, n, durationS);
        if (i == 0) {
            descend(stops[0], kOrbitHeightM, 0.0, arriveS);
        } else {
            const GlobeTourStop& from = stops[i - 1];
            const GlobeTourStop& to = stops[i];
            // High enough for both to be in view on the way across (the view is about as wide
            // as the height), and well above either end.
            const double lowest = std::max({from.endHeightM, to.endHeightM, 0.0}) + kTourLowestHopM;
            const double hopM = std::min(std::max(roughDistanceM(from, to), lowest), kOrbitHeightM);
            add(startS + kTourClimbEnds * share, from, hopM, -90.0);
            descend(to, hopM, startS + kTourCrossingEnds * share, arriveS);
        }
        // The hold: the same pose again, so the spline stops there (PathSpline's true hold).
        if (i + 1 < n) add(double(i + 1) * share, stops[i], stops[i].endHeightM, -5.0);
    }
    auto path = fromKeyframes(std::move(keyframes));
    TERRAIN_ASSERT(path.ok(), "GlobeCameraPath::fromTour built an invalid path");
    return std::move(path).value();
}

GlobeCameraPath::Segment GlobeCameraPath::segmentAt(double timeS) const {
    const std::size_t n = m_keyframes.size();
    double t = timeS;
    if (!(t > startS())) t = startS();  // also catches NaN
    if (t > endS()) t = endS();
    Segment segment;
    if (n > 1) {
        const auto after = std::upper_bound(m_times.begin(), m_times.end(), t);
        segment.i = std::min(static_cast<std::size_t>(after - m_times.begin()) - 1, n - 2);
    }
    segment.j = std::min(segment.i + 1, n - 1);
    segment.dt = m_times[segment.j] - m_times[segment.i];
    segment.s = segment.dt > 0.0 ? (t - m_times[segment.i]) / segment.dt : 0.0;
    return segment;
}

GlobePose GlobeCameraPath::poseAt(double timeS) const {
    const Segment g = segmentAt(timeS);
    const auto value = [&](int c) {
        return path_spline::hermite(m_values[c][g.i], m_tangents[c][g.i], m_values[c][g.j],
                                    m_tangents[c][g.j], g.dt, g.s);
    };
    GlobePose pose;
    pose.where.latitudeDeg = std::clamp(value(kLatitude), -90.0, 90.0);
    pose.where.longitudeDeg = wrap180(value(kLongitude));
    pose.where.height = std::sinh(value(kHeight));
    pose.headingDeg = wrap180(value(kHeading));
    pose.pitchDeg = std::clamp(value(kPitch), -90.0, 90.0);
    return pose;
}

double GlobeCameraPath::fovYDegreesAt(double timeS) const {
    const Segment g = segmentAt(timeS);
    const double a = m_keyframes[g.i].fovYDegrees, b = m_keyframes[g.j].fovYDegrees;
    // Smoothstep: C1 at the keyframes and never outside [a, b].
    return a + (b - a) * g.s * g.s * (3.0 - 2.0 * g.s);
}

void GlobeCameraPath::apply(double timeS, Camera& camera) const {
    placeOnGlobe(camera, poseAt(timeS));
    camera.fovY = fovYDegreesAt(timeS) * (std::numbers::pi / 180.0);
}

}  // namespace terrain::runtime
