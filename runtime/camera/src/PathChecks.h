// PathChecks: the keyframe checks both camera paths share, worded once in the file's key
// names (docs/camera-path.md): at least one keyframe, finite times increasing strictly, a
// field of view within (0, 180), and spline speeds that do not overflow. Internal to
// terrain::camera.
#pragma once

#include <fmt/format.h>

#include <cmath>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace terrain::runtime::path_checks {

inline constexpr std::string_view kEmpty =
    "\"keyframes\" is empty; a path needs at least one keyframe";

/// What is wrong with keyframe i's time, or nothing: it must be finite and after the one
/// before.
template <typename Keyframe>
std::optional<std::string> timeProblem(const std::vector<Keyframe>& keyframes, std::size_t i) {
    const double t = keyframes[i].timeS;
    if (!std::isfinite(t))
        return fmt::format("keyframes[{}].time_s is {}; it must be finite", i, t);
    if (i > 0 && !(t > keyframes[i - 1].timeS))
        return fmt::format(
            "keyframes[{}].time_s is {}, not after keyframes[{}].time_s {}; times must "
            "increase strictly",
            i, t, i - 1, keyframes[i - 1].timeS);
    return std::nullopt;
}

/// What is wrong with keyframe i's field of view, or nothing.
inline std::optional<std::string> fovProblem(std::size_t i, double fovYDegrees) {
    if (fovYDegrees > 0.0 && fovYDegrees < 180.0) return std::nullopt;
    return fmt::format(
        "keyframes[{}].fov_y_deg is {}; a field of view lies strictly between 0 and 180 degrees", i,
        fovYDegrees);
}

/// Finite keyframes can still be too far apart for their times (1e300 m in 1e-300 s).
inline std::string overflowProblem(std::string_view sourceName, std::size_t keyframe) {
    return fmt::format(
        "{}: keyframes[{}]: the speed toward a neighbouring keyframe overflows; the keyframes "
        "are too far apart for their times",
        sourceName, keyframe);
}

}  // namespace terrain::runtime::path_checks
