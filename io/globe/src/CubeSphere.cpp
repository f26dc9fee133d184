#include "terrain/globe/CubeSphere.h"

#include "terrain/base/Assert.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace terrain::globe {

namespace {

// See the header for the orientation rule; the four side faces run east along `right` and
// south along `down`, and each polar face's bottom row meets face +X along x = ±1.
constexpr std::array<FaceFrame, kCubeFaces> kFrames{{
    {{1, 0, 0}, {0, 1, 0}, {0, 0, -1}},    // +X
    {{0, 1, 0}, {-1, 0, 0}, {0, 0, -1}},   // +Y
    {{-1, 0, 0}, {0, -1, 0}, {0, 0, -1}},  // −X
    {{0, -1, 0}, {1, 0, 0}, {0, 0, -1}},   // −Y
    {{0, 0, 1}, {0, 1, 0}, {1, 0, 0}},     // +Z
    {{0, 0, -1}, {0, 1, 0}, {-1, 0, 0}},   // −Z
}};

constexpr double kQuarterPi = std::numbers::pi / 4.0;

}  // namespace

const FaceFrame& faceFrame(int face) {
    TERRAIN_ASSERT(face >= 0 && face < kCubeFaces);
    return kFrames[static_cast<std::size_t>(face)];
}

double cubeCoordinate(double faceCoordinate) {
    // 2s − 1 is exact for the dyadic sample positions of a patch grid; tan(π/4) is not 1 in
    // double, so the edges are set exactly.
    const double a = 2.0 * faceCoordinate - 1.0;
    const double magnitude = std::abs(a);
    const double c = magnitude == 1.0 ? 1.0 : std::tan(kQuarterPi * magnitude);
    return a < 0.0 ? -c : c;
}

double faceCoordinate(double cubeCoordinate) {
    return (std::atan(cubeCoordinate) / kQuarterPi + 1.0) * 0.5;
}

glm::dvec3 cubePoint(int face, double s, double t) {
    return cubePointOfCubeCoordinates(face, cubeCoordinate(s), cubeCoordinate(t));
}

glm::dvec3 cubePointOfCubeCoordinates(int face, double cs, double ct) {
    const FaceFrame& frame = faceFrame(face);
    // Integer unit axes: every component is exactly ±1, ±cs, ±ct or 0.
    return glm::dvec3(frame.normal) + cs * glm::dvec3(frame.right) + ct * glm::dvec3(frame.down);
}

glm::dvec3 directionOfCubePoint(const glm::dvec3& p) {
    return p / std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z);
}

glm::dvec3 directionOf(int face, double s, double t) {
    return directionOfCubePoint(cubePoint(face, s, t));
}

FacePoint facePointOf(const glm::dvec3& direction) {
    int best = 0;
    double bestDot = -1.0;
    for (int face = 0; face < kCubeFaces; ++face) {
        const double d = glm::dot(direction, glm::dvec3(kFrames[face].normal));
        if (d > bestDot) {
            bestDot = d;
            best = face;
        }
    }
    const FaceFrame& frame = kFrames[static_cast<std::size_t>(best)];
    const double cs = glm::dot(direction, glm::dvec3(frame.right)) / bestDot;
    const double ct = glm::dot(direction, glm::dvec3(frame.down)) / bestDot;
    return {best, std::clamp(faceCoordinate(cs), 0.0, 1.0),
            std::clamp(faceCoordinate(ct), 0.0, 1.0)};
}

}  // namespace terrain::globe
