// NativeOffset: where a native tile's samples lie, camera-relative in float (docs/globe.md,
// "Native leaves"; SurfaceOffset.h does the same for face patches and says why no
// planet-sized float may be formed). A native tile is a tile of a source's own
// longitude/latitude grid: its sample (i, j) lies at longitude λ = west + (x·quads + i + ½)·Δλ
// and latitude φ = north − (y·quads + j + ½)·Δφ, at height h along the ellipsoid normal
// d = (cos φ cos λ, cos φ sin λ, sin φ). With a reference point (λ0, φ0) on the tile, from the
// CPU in double with O − camera, the stage evaluates P − camera = (O − camera) + (S(d) − S(d0))
// + h·d, forming every difference from small quantities:
//   cos a − cos a0 = −2 sin(a0 + Δ/2) sin(Δ/2),   sin a − sin a0 = 2 cos(a0 + Δ/2) sin(Δ/2)
//   Δd_x = cos φ (cos λ − cos λ0) + cos λ0 (cos φ − cos φ0), Δd_y likewise, Δd_z = sin φ − sin φ0
// and S(d) − S(d0) as SurfaceOffset.h does. This header is the CPU twin of the GLSL
// (shaders/surface_globe.glsl, nativeDirection); NativeOffsetTest holds it to double precision.
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstdint>

namespace terrain::globe {

/// A native grid's geometry: its north-west pixel corner and pixel size, degrees, and the
/// quads of its tiles.
struct NativeGridGeometry {
    double westDeg = 0.0;
    double northDeg = 0.0;
    double pixelLonDeg = 1.0;
    double pixelLatDeg = 1.0;
    int quads = 128;

    /// Longitude and latitude, degrees, of tile (x, y)'s point at tile coordinates (u, v) in
    /// [0, 1]² (sample i at u = i / quads).
    glm::dvec2 lonLatDeg(std::int64_t x, std::int64_t y, double u, double v) const;
};

/// What one native tile needs to place its vertices camera-relative in float. Computed in
/// double from the float reference coordinates, so the stage's differences start from them.
struct NativeSurfaceFrame {
    float lonPerU = 0.0f;  ///< radians of longitude per unit of u (quads · Δλ)
    float latPerV = 0.0f;  ///< radians of latitude per unit of v (−quads · Δφ: v runs south)
    float u0 = 0.0f;       ///< the reference point's tile coordinates
    float v0 = 0.0f;
    float lon0 = 0.0f;  ///< its longitude and latitude, radians
    float lat0 = 0.0f;
    glm::vec3 direction0{0.0f};        ///< d0
    float sqrtG0 = 0.0f;               ///< √(1 − e²·d0z²)
    float primeVertical0 = 0.0f;       ///< N0 = a / √g0
    glm::vec3 originFromCamera{0.0f};  ///< S(d0) − camera, in double
};

/// The frame of tile (x, y) of `grid` with its reference point at (u0, v0), for a camera at
/// ECEF `camera`.
NativeSurfaceFrame makeNativeSurfaceFrame(const NativeGridGeometry& grid, std::int64_t x,
                                          std::int64_t y, double u0, double v0,
                                          const glm::dvec3& camera);

/// The tile coordinates, clamped to [0, 1]², of the camera's nadir (cameraUp: the ellipsoid
/// normal at the camera, Wgs84::upAt).
glm::dvec2 nearestNativeCoordinates(const NativeGridGeometry& grid, std::int64_t x, std::int64_t y,
                                    const glm::dvec3& cameraUp);

/// The camera-relative position of tile coordinates (u, v) at height h, in float only; and
/// the ellipsoid normal there.
glm::vec3 nativeCameraRelativePosition(const NativeSurfaceFrame& frame, float u, float v,
                                       float height, glm::vec3* direction = nullptr);

}  // namespace terrain::globe
