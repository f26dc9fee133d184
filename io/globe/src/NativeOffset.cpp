#include "terrain/globe/NativeOffset.h"

#include "terrain/globe/SurfaceOffset.h"
#include "terrain/globe/Wgs84.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace terrain::globe {

namespace {

constexpr double kRadian = std::numbers::pi / 180.0;

}  // namespace

glm::dvec2 NativeGridGeometry::lonLatDeg(std::int64_t x, std::int64_t y, double u, double v) const {
    const double q = static_cast<double>(quads);
    return {westDeg + (static_cast<double>(x) * q + u * q + 0.5) * pixelLonDeg,
            northDeg - (static_cast<double>(y) * q + v * q + 0.5) * pixelLatDeg};
}

NativeSurfaceFrame makeNativeSurfaceFrame(const NativeGridGeometry& grid, std::int64_t x,
                                          std::int64_t y, double requestedU0, double requestedV0,
                                          const glm::dvec3& camera) {
    // The stage measures Δλ and Δφ from the float u0 and v0: the reference is theirs.
    const double u0 = static_cast<float>(requestedU0);
    const double v0 = static_cast<float>(requestedV0);
    const glm::dvec2 reference = grid.lonLatDeg(x, y, u0, v0);
    // d0 and S(d0) − camera in double at the exact reference: the stage's float λ0 and φ0
    // (a float holds π to 1e-7 rad, 0.6 m of longitude) appear only inside the sines and
    // cosines that multiply a small difference, where their rounding is a relative error of
    // that difference, as the face patches' α0 is (SurfaceOffset.h).
    const double lon = reference.x * kRadian, lat = reference.y * kRadian;
    const auto lon0 = static_cast<float>(lon);
    const auto lat0 = static_cast<float>(lat);
    const glm::dvec3 direction0(std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon),
                                std::sin(lat));
    const double g0 = 1.0 - Wgs84::kEccentricitySquared * direction0.z * direction0.z;

    NativeSurfaceFrame frame;
    frame.lonPerU = static_cast<float>(grid.quads * grid.pixelLonDeg * kRadian);
    frame.latPerV = static_cast<float>(-grid.quads * grid.pixelLatDeg * kRadian);
    frame.u0 = static_cast<float>(u0);
    frame.v0 = static_cast<float>(v0);
    frame.lon0 = lon0;
    frame.lat0 = lat0;
    frame.direction0 = glm::vec3(direction0);
    frame.sqrtG0 = static_cast<float>(std::sqrt(g0));
    frame.primeVertical0 = static_cast<float>(Wgs84::kEquatorialRadius / std::sqrt(g0));
    frame.originFromCamera = glm::vec3(Wgs84::pointAlongNormal(direction0, 0.0) - camera);
    return frame;
}

glm::dvec2 nearestNativeCoordinates(const NativeGridGeometry& grid, std::int64_t x, std::int64_t y,
                                    const glm::dvec3& cameraUp) {
    const Geodetic nadir = Wgs84::geodeticOfNormal(cameraUp);
    const glm::dvec2 corner = grid.lonLatDeg(x, y, 0.0, 0.0);
    const double span = static_cast<double>(grid.quads);
    // The longitude nearest the tile's, across the antimeridian if need be.
    double longitude = nadir.longitudeDeg;
    const double middle = corner.x + 0.5 * span * grid.pixelLonDeg;
    longitude += 360.0 * std::round((middle - longitude) / 360.0);
    const double u = (longitude - corner.x) / (span * grid.pixelLonDeg);
    const double v = (corner.y - nadir.latitudeDeg) / (span * grid.pixelLatDeg);
    return {std::clamp(u, 0.0, 1.0), std::clamp(v, 0.0, 1.0)};
}

glm::vec3 nativeCameraRelativePosition(const NativeSurfaceFrame& frame, float u, float v,
                                       float height, glm::vec3* directionOut) {
    const float deltaLon = frame.lonPerU * (u - frame.u0);
    const float deltaLat = frame.latPerV * (v - frame.v0);
    const float lat = frame.lat0 + deltaLat;
    const float halfLon = std::sin(0.5f * deltaLon), halfLat = std::sin(0.5f * deltaLat);
    const float deltaCosLon = -2.0f * std::sin(frame.lon0 + 0.5f * deltaLon) * halfLon;
    const float deltaSinLon = 2.0f * std::cos(frame.lon0 + 0.5f * deltaLon) * halfLon;
    const float deltaCosLat = -2.0f * std::sin(frame.lat0 + 0.5f * deltaLat) * halfLat;
    const float deltaSinLat = 2.0f * std::cos(frame.lat0 + 0.5f * deltaLat) * halfLat;
    const float cosLat = std::cos(lat);
    const glm::vec3 deltaDirection(cosLat * deltaCosLon + std::cos(frame.lon0) * deltaCosLat,
                                   cosLat * deltaSinLon + std::sin(frame.lon0) * deltaCosLat,
                                   deltaSinLat);
    const glm::vec3 direction = frame.direction0 + deltaDirection;
    if (directionOut != nullptr) *directionOut = direction;

    return surfaceOffsetFromDirection(frame.originFromCamera, frame.direction0, frame.sqrtG0,
                                      deltaDirection, height);
}

}  // namespace terrain::globe
