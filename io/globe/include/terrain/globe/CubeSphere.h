// CubeSphere: the planet's tiling without poles (DESIGN.md, "The globe"). Six cube faces, each
// a square of face coordinates (s, t) in [0, 1]² (s along the face's `right` axis, t along its
// `down` axis, so a face reads like a raster: columns east-ish, rows south-ish). A face point
// goes to the cube surface through the tangent adjustment of Google's S2 library,
// c = tan(π/4 · (2s − 1)), which keeps the spacing of a regular (s, t) grid within √2 over a
// face (a plain gnomonic cube varies about 5×), and the normalised cube point is the outward
// ellipsoid normal of the sample (Wgs84::pointAlongNormal), so heights displace along it and
// its geodetic latitude is asin(n.z). Poles and the antimeridian are interior points of faces;
// only the 12 cube edges are special, and there both faces build the identical cube point (a
// component is exactly ±1, the others come from the same odd-symmetric adjustment), so
// samples on a shared edge are bit-identical from either side.
#pragma once

#include <glm/vec3.hpp>

#include <array>

namespace terrain::globe {

inline constexpr int kCubeFaces = 6;

/// Face indices: 0 +X (lon 0°), 1 +Y (lon 90°E), 2 −X (lon 180°), 3 −Y (lon 90°W),
/// 4 +Z (north pole), 5 −Z (south pole).
enum class CubeFace : int { PositiveX = 0, PositiveY, NegativeX, NegativeY, North, South };

/// A face's axes, integer unit vectors in ECEF: the cube point of face coordinates (s, t) is
/// normal + c(s)·right + c(t)·down, and right × down = −normal (a raster seen from outside).
struct FaceFrame {
    glm::ivec3 normal;
    glm::ivec3 right;  ///< the direction s grows in
    glm::ivec3 down;   ///< the direction t grows in
};

const FaceFrame& faceFrame(int face);

/// A point of a face: s and t in [0, 1] on the face (slightly outside for apron samples).
struct FacePoint {
    int face = 0;
    double s = 0.0;
    double t = 0.0;
};

/// The tangent adjustment: face coordinate in [0, 1] to cube coordinate in [−1, 1]. Exactly ±1
/// at the face edges and odd-symmetric about 0.5 (c(1 − s) = −c(s) bit for bit), which is what
/// makes shared edges identical from both faces.
double cubeCoordinate(double faceCoordinate);
/// Its inverse: (4/π · atan(c) + 1) / 2.
double faceCoordinate(double cubeCoordinate);

/// The point of the cube surface (one component ±1) of a face point.
glm::dvec3 cubePoint(int face, double s, double t);
/// The same from the point's cube coordinates, cubeCoordinate(s) and cubeCoordinate(t).
glm::dvec3 cubePointOfCubeCoordinates(int face, double cs, double ct);
/// A cube point's unit direction (the ellipsoid normal): what directionOf returns.
glm::dvec3 directionOfCubePoint(const glm::dvec3& cube);
/// The unit direction (the ellipsoid normal) of a face point.
glm::dvec3 directionOf(int face, double s, double t);
/// The face point of a direction (any length > 0): the face of its largest component (ties go
/// to the lowest face index), s and t in [0, 1].
FacePoint facePointOf(const glm::dvec3& direction);

}  // namespace terrain::globe
