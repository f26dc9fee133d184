// Wgs84: the WGS84 ellipsoid in earth-centred, earth-fixed (ECEF) metres, double precision.
// Geodetic coordinates go through GeographicLib::Geocentric (Karney's exact conversions);
// what the cube-sphere and the draw need most, the point of the ellipsoid whose outward
// normal is a given unit vector, is closed-form and needs no trigonometry.
#pragma once

#include <glm/vec3.hpp>

#include <algorithm>

namespace terrain::globe {

/// Latitude and longitude in degrees (geodetic, WGS84), height in metres above the
/// ellipsoid along its normal.
struct Geodetic {
    double latitudeDeg = 0.0;
    double longitudeDeg = 0.0;
    double height = 0.0;
};

/// The ellipsoid's principal radii of curvature at a latitude, metres: along the meridian (M)
/// and across it (the prime vertical, N); a degree of latitude is M·π/180 metres there, a
/// degree of longitude N·cos φ·π/180.
struct CurvatureRadii {
    double meridian = 0.0;
    double primeVertical = 0.0;
};

struct Wgs84 {
    static constexpr double kEquatorialRadius = 6378137.0;      ///< a, metres
    static constexpr double kFlattening = 1.0 / 298.257223563;  ///< f
    static constexpr double kEccentricitySquared = kFlattening * (2.0 - kFlattening);  ///< e²
    static constexpr double kPolarRadius = kEquatorialRadius * (1.0 - kFlattening);    ///< b
    /// The smallest radius of curvature of the ellipsoid, b²/a (the meridian's at the
    /// equator): what bounds how far a chord between two surface points strays from it.
    static constexpr double kMinCurvatureRadius = kPolarRadius * kPolarRadius / kEquatorialRadius;
    /// The largest, a²/b (at the poles).
    static constexpr double kMaxCurvatureRadius =
        kEquatorialRadius * kEquatorialRadius / kPolarRadius;

    /// M = a(1 − e²)/w³ and N = a/w, w = √(1 − e² sin² φ).
    static CurvatureRadii curvatureRadiiAt(double latitudeDeg);

    /// ECEF position of a geodetic point (GeographicLib::Geocentric::Forward).
    static glm::dvec3 toEcef(const Geodetic& point);
    /// Geodetic coordinates of an ECEF position (GeographicLib::Geocentric::Reverse).
    static Geodetic toGeodetic(const glm::dvec3& ecef);

    /// The outward unit normal of the ellipsoid at a latitude and longitude.
    static glm::dvec3 normalAt(double latitudeDeg, double longitudeDeg);
    /// The ellipsoid normal through an ECEF point: the direction "up" there, which is not the
    /// point's direction from the centre (geodetic and geocentric latitude differ by up to 0.19°).
    static glm::dvec3 upAt(const glm::dvec3& ecef);
    /// Latitude and longitude (degrees) whose normal is `unitNormal`: the geodetic latitude is
    /// asin(n.z), the longitude atan2(n.y, n.x).
    static Geodetic geodeticOfNormal(const glm::dvec3& unitNormal, double height = 0.0);

    /// The point at `height` above the ellipsoid along the normal `unitNormal`:
    /// (N + h)·(nx, ny, 0) + ((1 − e²)·N + h)·(0, 0, nz) with the prime-vertical radius
    /// N = a / √(1 − e²·nz²), since sin φ = nz and cos φ·(cos λ, sin λ) = (nx, ny).
    static glm::dvec3 pointAlongNormal(const glm::dvec3& unitNormal, double height);
    /// pointAlongNormal's two radii, N + h and (1 − e²)·N + h, which depend on nz alone: kept
    /// for a row of normals of one latitude, each point is then three products, to the bit
    /// pointAlongNormal's (which is made of them).
    struct RadiiAlongNormal {
        double horizontal = 0.0, vertical = 0.0;
    };
    static RadiiAlongNormal radiiAlongNormal(double unitNormalZ, double height);
    static glm::dvec3 pointAlongNormal(const glm::dvec3& unitNormal,
                                       const RadiiAlongNormal& radii) {
        return {radii.horizontal * unitNormal.x, radii.horizontal * unitNormal.y,
                radii.vertical * std::clamp(unitNormal.z, -1.0, 1.0)};
    }
};

}  // namespace terrain::globe
