#include "terrain/globe/Wgs84.h"

#include <GeographicLib/Geocentric.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace terrain::globe {

namespace {

const GeographicLib::Geocentric& geocentric() {
    // GeographicLib's own WGS84 constants are the same as ours; building it from ours keeps
    // one definition of the ellipsoid in this project.
    static const GeographicLib::Geocentric wgs84(Wgs84::kEquatorialRadius, Wgs84::kFlattening);
    return wgs84;
}

constexpr double kDegree = std::numbers::pi / 180.0;

}  // namespace

glm::dvec3 Wgs84::toEcef(const Geodetic& point) {
    glm::dvec3 ecef{0.0};
    geocentric().Forward(point.latitudeDeg, point.longitudeDeg, point.height, ecef.x, ecef.y,
                         ecef.z);
    return ecef;
}

Geodetic Wgs84::toGeodetic(const glm::dvec3& ecef) {
    Geodetic point;
    geocentric().Reverse(ecef.x, ecef.y, ecef.z, point.latitudeDeg, point.longitudeDeg,
                         point.height);
    return point;
}

CurvatureRadii Wgs84::curvatureRadiiAt(double latitudeDeg) {
    const double s = std::sin(latitudeDeg * kDegree);
    const double w = std::sqrt(1.0 - kEccentricitySquared * s * s);
    return {kEquatorialRadius * (1.0 - kEccentricitySquared) / (w * w * w), kEquatorialRadius / w};
}

glm::dvec3 Wgs84::normalAt(double latitudeDeg, double longitudeDeg) {
    const double lat = latitudeDeg * kDegree;
    const double lon = longitudeDeg * kDegree;
    return {std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon), std::sin(lat)};
}

glm::dvec3 Wgs84::upAt(const glm::dvec3& ecef) {
    const Geodetic point = toGeodetic(ecef);
    return normalAt(point.latitudeDeg, point.longitudeDeg);
}

Geodetic Wgs84::geodeticOfNormal(const glm::dvec3& unitNormal, double height) {
    const double horizontal = std::hypot(unitNormal.x, unitNormal.y);
    return {std::atan2(unitNormal.z, horizontal) / kDegree,
            std::atan2(unitNormal.y, unitNormal.x) / kDegree, height};
}

Wgs84::RadiiAlongNormal Wgs84::radiiAlongNormal(double unitNormalZ, double height) {
    const double nz = std::clamp(unitNormalZ, -1.0, 1.0);
    const double primeVertical =
        kEquatorialRadius / std::sqrt(1.0 - kEccentricitySquared * nz * nz);
    return {primeVertical + height, (1.0 - kEccentricitySquared) * primeVertical + height};
}

glm::dvec3 Wgs84::pointAlongNormal(const glm::dvec3& unitNormal, double height) {
    return pointAlongNormal(unitNormal, radiiAlongNormal(unitNormal.z, height));
}

}  // namespace terrain::globe
