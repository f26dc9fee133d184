#include "terrain/globe/NativeOffset.h"

#include "terrain/globe/CubeSphere.h"
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
                                    const glm::dvec3& cameraUp, const NativeWindow& window) {
    const Geodetic nadir = Wgs84::geodeticOfNormal(cameraUp);
    const glm::dvec2 corner = grid.lonLatDeg(x, y, 0.0, 0.0);
    const double span = static_cast<double>(grid.quads);
    // The longitude nearest the tile's, across the antimeridian if need be.
    double longitude = nadir.longitudeDeg;
    const double middle = corner.x + 0.5 * span * grid.pixelLonDeg;
    longitude += 360.0 * std::round((middle - longitude) / 360.0);
    const double u = (longitude - corner.x) / (span * grid.pixelLonDeg);
    const double v = (corner.y - nadir.latitudeDeg) / (span * grid.pixelLatDeg);
    return {std::clamp(u, window.u0(), window.u0() + window.size()),
            std::clamp(v, window.v0(), window.v0() + window.size())};
}

glm::vec3 nativeDeltaDirection(const NativeSurfaceFrame& frame, float u, float v) {
    const float deltaLon = frame.lonPerU * (u - frame.u0);
    const float deltaLat = frame.latPerV * (v - frame.v0);
    const float lat = frame.lat0 + deltaLat;
    const float halfLon = std::sin(0.5f * deltaLon), halfLat = std::sin(0.5f * deltaLat);
    const float deltaCosLon = -2.0f * std::sin(frame.lon0 + 0.5f * deltaLon) * halfLon;
    const float deltaSinLon = 2.0f * std::cos(frame.lon0 + 0.5f * deltaLon) * halfLon;
    const float deltaCosLat = -2.0f * std::sin(frame.lat0 + 0.5f * deltaLat) * halfLat;
    const float deltaSinLat = 2.0f * std::cos(frame.lat0 + 0.5f * deltaLat) * halfLat;
    const float cosLat = std::cos(lat);
    return {cosLat * deltaCosLon + std::cos(frame.lon0) * deltaCosLat,
            cosLat * deltaSinLon + std::sin(frame.lon0) * deltaCosLat, deltaSinLat};
}

glm::vec3 nativeCameraRelativePosition(const NativeSurfaceFrame& frame, float u, float v,
                                       float height, glm::vec3* directionOut) {
    const glm::vec3 deltaDirection = nativeDeltaDirection(frame, u, v);
    if (directionOut != nullptr) *directionOut = frame.direction0 + deltaDirection;
    return surfaceOffsetFromDirection(frame.originFromCamera, frame.direction0, frame.sqrtG0,
                                      deltaDirection, height);
}

std::optional<glm::dvec2> patchCoordinatesOf(const GlobePatchId& patch,
                                             const glm::dvec3& direction) {
    const FaceFrame& face = faceFrame(patch.face);
    const double along = glm::dot(direction, glm::dvec3(face.normal));
    if (along <= 0.5) return std::nullopt;
    const double n = static_cast<double>(patchesPerFaceSide(patch.level));
    const double s = faceCoordinate(glm::dot(direction, glm::dvec3(face.right)) / along);
    const double t = faceCoordinate(glm::dot(direction, glm::dvec3(face.down)) / along);
    return glm::dvec2(s * n - static_cast<double>(patch.x), t * n - static_cast<double>(patch.y));
}

NativeImageryFrame makeNativeImageryFrame(const NativeGridGeometry& grid, std::int64_t x,
                                          std::int64_t y, const NativeSurfaceFrame& frame,
                                          const GlobePatchId& patch) {
    // The exact d0 the frame was made at (its float u0, v0), in double.
    const glm::dvec2 reference = grid.lonLatDeg(x, y, frame.u0, frame.v0);
    const double lon = reference.x * kRadian, lat = reference.y * kRadian;
    const glm::dvec3 direction0(std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon),
                                std::sin(lat));
    NativeImageryFrame imagery;
    imagery.face = patch.face;
    // A d0 off the face's hemisphere has no coordinates; the caller draws no imagery there.
    const glm::dvec2 uv0 = patchCoordinatesOf(patch, direction0).value_or(glm::dvec2(0.0));
    imagery.u0 = static_cast<float>(uv0.x);
    imagery.v0 = static_cast<float>(uv0.y);
    imagery.uPerAlpha =
        static_cast<float>(double(patchesPerFaceSide(patch.level)) / (0.5 * std::numbers::pi));
    return imagery;
}

glm::vec2 nativeImageryCoordinates(const NativeImageryFrame& imagery, const glm::vec3& direction0,
                                   const glm::vec3& deltaDirection) {
    const FaceFrame& face = faceFrame(imagery.face);
    const glm::vec3 normal(face.normal), right(face.right), down(face.down);
    const float along0 = glm::dot(direction0, normal);
    const float along = along0 + glm::dot(deltaDirection, normal);
    const glm::vec2 cube0(glm::dot(direction0, right) / along0,
                          glm::dot(direction0, down) / along0);
    const glm::vec2 deltaCube =
        (glm::vec2(glm::dot(deltaDirection, right), glm::dot(deltaDirection, down)) * along0 -
         glm::vec2(glm::dot(direction0, right), glm::dot(direction0, down)) *
             glm::dot(deltaDirection, normal)) /
        (along * along0);
    const glm::vec2 cube = cube0 + deltaCube;
    const glm::vec2 ratio = deltaCube / (1.0f + cube * cube0);
    const glm::vec2 deltaAngle(std::atan(ratio.x), std::atan(ratio.y));
    return glm::vec2(imagery.u0, imagery.v0) + deltaAngle * imagery.uPerAlpha;
}

std::optional<glm::dvec4> nativeTileExtentOn(const NativeGridGeometry& grid, std::int64_t x,
                                             std::int64_t y, const GlobePatchId& patch) {
    constexpr int kPointsPerEdge = 17;
    glm::dvec4 box(1e300, 1e300, -1e300, -1e300);
    for (int edge = 0; edge < 4; ++edge) {
        for (int k = 0; k < kPointsPerEdge; ++k) {
            const double f = double(k) / double(kPointsPerEdge - 1);
            const glm::dvec2 uv = edge == 0   ? glm::dvec2(f, 0.0)
                                  : edge == 1 ? glm::dvec2(f, 1.0)
                                  : edge == 2 ? glm::dvec2(0.0, f)
                                              : glm::dvec2(1.0, f);
            const glm::dvec2 lonLat = grid.lonLatDeg(x, y, uv.x, uv.y);
            const double lon = lonLat.x * kRadian;
            const double lat = std::clamp(lonLat.y, -90.0, 90.0) * kRadian;
            const std::optional<glm::dvec2> at =
                patchCoordinatesOf(patch, glm::dvec3(std::cos(lat) * std::cos(lon),
                                                     std::cos(lat) * std::sin(lon), std::sin(lat)));
            if (!at) return std::nullopt;
            box = glm::dvec4(std::min(box.x, at->x), std::min(box.y, at->y), std::max(box.z, at->x),
                             std::max(box.w, at->y));
        }
    }
    return box;
}

}  // namespace terrain::globe
