// PathSpline: the keyframe spline both camera paths play back (docs/camera-path.md,
// "Playback"): cubic Hermite segments with Catmull–Rom tangents shortened after Fritsch &
// Carlson (1980). Internal to terrain::camera.
#pragma once

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <span>

namespace terrain::runtime::path_spline {

inline double magnitude(double v) { return std::abs(v); }
inline double magnitude(const glm::dvec3& v) { return glm::length(v); }

// Catmull–Rom tangent at keyframe i of a run of keyframes; hasPrevious and hasNext say
// whether i − 1 and i + 1 belong to the run. The run's end points are duplicated one
// segment beyond the end, as a uniform Catmull–Rom spline duplicates them: the end
// tangent is half the end chord's slope.
//
// The tangent is then shortened, where needed, to 3× the slower of the two neighbouring
// chord speeds. That keeps each segment inside Fritsch & Carlson's (1980) monotonicity
// region along its own chord: after a short step the camera never swings back before a
// long one, and two keyframes at the same place are a true hold. Tangents stay one per
// keyframe, so the spline stays C1.
template <typename T>
T catmullRomTangent(std::span<const T> values, std::span<const double> times, std::size_t i,
                    bool hasPrevious, bool hasNext) {
    if (!hasPrevious && !hasNext) return T(0.0);
    if (!hasPrevious) return (values[i + 1] - values[i]) / (2.0 * (times[i + 1] - times[i]));
    if (!hasNext) return (values[i] - values[i - 1]) / (2.0 * (times[i] - times[i - 1]));
    const T tangent = (values[i + 1] - values[i - 1]) / (times[i + 1] - times[i - 1]);
    const double limit =
        3.0 * std::min(magnitude(values[i] - values[i - 1]) / (times[i] - times[i - 1]),
                       magnitude(values[i + 1] - values[i]) / (times[i + 1] - times[i]));
    const double length = magnitude(tangent);
    return length > limit ? tangent * (limit / length) : tangent;
}

// Cubic Hermite basis on a segment of length dt at s ∈ [0, 1]. Exact at s = 0 and s = 1,
// so the path passes through its keyframes bit for bit.
template <typename T>
T hermite(const T& p0, const T& m0, const T& p1, const T& m1, double dt, double s) {
    const double s2 = s * s;
    const double s3 = s2 * s;
    const double h00 = 2.0 * s3 - 3.0 * s2 + 1.0;
    const double h10 = s3 - 2.0 * s2 + s;
    const double h01 = -2.0 * s3 + 3.0 * s2;
    const double h11 = s3 - s2;
    return h00 * p0 + (h10 * dt) * m0 + h01 * p1 + (h11 * dt) * m1;
}

}  // namespace terrain::runtime::path_spline
