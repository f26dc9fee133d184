#include "terrain/runtime/GlobeCamera.h"

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace terrain::runtime {

namespace {
constexpr double kDegree = std::numbers::pi / 180.0;
}

glm::dmat3 eastNorthUp(double latitudeDeg, double longitudeDeg) {
    const double lat = latitudeDeg * kDegree;
    const double lon = longitudeDeg * kDegree;
    const glm::dvec3 east(-std::sin(lon), std::cos(lon), 0.0);
    const glm::dvec3 north(-std::sin(lat) * std::cos(lon), -std::sin(lat) * std::sin(lon),
                           std::cos(lat));
    const glm::dvec3 up(std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon),
                        std::sin(lat));
    return glm::dmat3(east, north, up);
}

void placeOnGlobe(Camera& camera, const GlobePose& pose) {
    camera.position = globe::Wgs84::toEcef(pose.where);
    camera.frame = eastNorthUp(pose.where.latitudeDeg, pose.where.longitudeDeg);
    camera.yaw = pose.headingDeg * kDegree;
    camera.pitch = std::clamp(pose.pitchDeg * kDegree, -Camera::kMaxPitch, Camera::kMaxPitch);
    camera.nearPlane = kGlobeNearPlaneM;
}

GlobePose globePoseOf(const Camera& camera) {
    GlobePose pose;
    pose.where = globe::Wgs84::toGeodetic(camera.position);
    const glm::dmat3 local =
        glm::transpose(eastNorthUp(pose.where.latitudeDeg, pose.where.longitudeDeg));
    const glm::dvec3 f = local * camera.forward();
    pose.headingDeg = std::atan2(f.x, f.y) / kDegree;
    pose.pitchDeg = std::asin(std::clamp(f.z, -1.0, 1.0)) / kDegree;
    return pose;
}

}  // namespace terrain::runtime
