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

#include "terrain/globe/GlobePatch.h"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cmath>
#include <cstdint>
#include <optional>

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

/// A window of a native tile (docs/globe.md, "Native windows"): the square [i, i + 1] ×
/// [j, j + 1] · 2^-depth of its tile coordinates, drawn as a patch of its own where the tile's
/// flat triangles would stray too far (its samples interpolated on the source's own
/// triangles). Depth 0 is the whole tile. Its tile coordinates are exact in float up to
/// kMaxDepth: (i·quads + s)·2^-depth, sample s of the window, has at most 8 + depth bits.
struct NativeWindow {
    static constexpr int kMaxDepth = 16;
    int depth = 0;
    std::int64_t i = 0, j = 0;

    double size() const { return std::ldexp(1.0, -depth); }
    double u0() const { return static_cast<double>(i) * size(); }
    double v0() const { return static_cast<double>(j) * size(); }
    /// Its quadrant `quadrant` (bit 0 east, bit 1 south) one level down.
    NativeWindow child(int quadrant) const {
        return {depth + 1, 2 * i + (quadrant & 1), 2 * j + (quadrant >> 1)};
    }
    bool operator==(const NativeWindow&) const = default;
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

/// The tile coordinates of the camera's nadir (cameraUp: the ellipsoid normal at the camera,
/// Wgs84::upAt), clamped to `window` (by default the whole tile, [0, 1]²).
glm::dvec2 nearestNativeCoordinates(const NativeGridGeometry& grid, std::int64_t x, std::int64_t y,
                                    const glm::dvec3& cameraUp, const NativeWindow& window = {});

/// Δd = d − d0 of tile coordinates (u, v), in float from small quantities (the header's
/// derivation): what the position and the imagery coordinates below start from.
glm::vec3 nativeDeltaDirection(const NativeSurfaceFrame& frame, float u, float v);

/// The camera-relative position of tile coordinates (u, v) at height h, in float only; and
/// the ellipsoid normal there.
glm::vec3 nativeCameraRelativePosition(const NativeSurfaceFrame& frame, float u, float v,
                                       float height, glm::vec3* direction = nullptr);

// Imagery on a native tile. The imagery's tiles are the cube faces', so each vertex of a native
// tile takes the patch coordinates (u, v) of its direction on one face patch P, whose imagery
// tree it walks (runtime/lod ImagerySelection). Like the position they are a reference plus a
// small difference, never the difference of two planet-sized numbers: P's coordinates of the
// frame's d0, from the CPU in double, plus, with n, r, w the face's normal, right and down
// axes and c = tan α the cube coordinate along r (β and w likewise),
//   tan α − tan α0 = ((Δd·r)·(d0·n) − (d0·r)·(Δd·n)) / ((d·n)·(d0·n))
//   α − α0         = atan((tan α − tan α0) / (1 + tan α · tan α0))
//   u − u0         = (α − α0) · du/dα,  du/dα = 2^level / (π/2)
// (CubeSphere.h: α = π/4 · (2s − 1), u = s · 2^level − x). GLSL twin: surface_globe.glsl,
// nativeImageryUv.

/// What a native tile's vertices need for their coordinates on face patch P.
struct NativeImageryFrame {
    int face = 0;
    float u0 = 0.0f;  ///< P's patch coordinates of the frame's d0, from double
    float v0 = 0.0f;
    float uPerAlpha = 0.0f;  ///< du/dα on P's level
};

/// The imagery frame of tile (x, y) of `grid`, placed by `frame`, on face patch `patch`.
NativeImageryFrame makeNativeImageryFrame(const NativeGridGeometry& grid, std::int64_t x,
                                          std::int64_t y, const NativeSurfaceFrame& frame,
                                          const GlobePatchId& patch);

/// P's patch coordinates of the direction d0 + Δd, in float only (the twin of the GLSL).
glm::vec2 nativeImageryCoordinates(const NativeImageryFrame& imagery, const glm::vec3& direction0,
                                   const glm::vec3& deltaDirection);

/// `patch`'s coordinates, in double, of the ellipsoid normal `direction` (unit), extended past
/// the patch's and its face's edges on the face's plane; none where the direction lies more
/// than 60° from the face's normal (the face itself reaches 54.7°).
std::optional<glm::dvec2> patchCoordinatesOf(const GlobePatchId& patch,
                                             const glm::dvec3& direction);

/// The box (u min, v min, u max, v max), in `patch`'s coordinates, of native tile (x, y)'s
/// outline, 17 points an edge; none where part of it lies more than 60° from the face's normal.
std::optional<glm::dvec4> nativeTileExtentOn(const NativeGridGeometry& grid, std::int64_t x,
                                             std::int64_t y, const GlobePatchId& patch);

}  // namespace terrain::globe
