// SurfaceOffset: globe positions in float without planet-sized float coordinates (DESIGN.md,
// "The globe", Positions). A float holds 6,378 km to about 0.5 m, so the tessellation stage
// must never form an ECEF coordinate, nor subtract two of them. Instead each patch gets, from
// the CPU in double, a reference point O on its surface (the patch point nearest the camera's
// nadir) and O − camera; the stage then evaluates
//
//     P(u, v, h) − camera = (O − camera) + (S(d) − S(d0)) + h·d
//
// where S(d) is the ellipsoid point of normal d (Wgs84::pointAlongNormal). Every difference
// in S(d) − S(d0) is rewritten so that it is formed from small quantities, never as the
// difference of two large ones:
//   tan α − tan α0          = sin(α − α0) / (cos α · cos α0)          (the tangent adjustment)
//   1/|q| − 1/|q0|          = −(|q|² − |q0|²) / (|q|·|q0|·(|q| + |q0|)),
//   |q|² − |q0|²            = Δc_s·(c_s + c_s0) + Δc_t·(c_t + c_t0)
//   N − N0 = a/√g − a/√g0   = −a·Δg / (√g·√g0·(√g + √g0)),  Δg = −e²·Δd_z·(d_z + d_z0)
//   S(d) − S(d0)            = N·M·Δd + (N − N0)·M·d0,        M = diag(1, 1, 1 − e²)
// so the result's error is a few float ulps of |P − O|, not of the planet's radius: within
// 10 km of the reference a few millimetres. This header is the CPU twin of the GLSL the draw
// will run; SurfaceOffsetTest holds it to a double-precision reference.
#pragma once

#include "terrain/globe/GlobePatch.h"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace terrain::globe {

/// What one patch needs to place its vertices camera-relative in float. Computed in double.
struct PatchSurfaceFrame {
    glm::vec3 normal{0.0f};  ///< the face's axes (CubeSphere.h), as floats
    glm::vec3 right{0.0f};
    glm::vec3 down{0.0f};
    float alphaPerU = 0.0f;  ///< dα/du = π/2 · 2^−level (α = π/4 · (2s − 1))
    float u0 = 0.0f;         ///< the reference point's patch coordinates, [0, 1]
    float v0 = 0.0f;
    float alpha0 = 0.0f;  ///< α and β (the same for t) at the reference point
    float beta0 = 0.0f;
    float cubeS0 = 0.0f;  ///< tan α0, tan β0: the reference point's cube coordinates
    float cubeT0 = 0.0f;
    float inverseLength0 = 0.0f;  ///< 1 / |q0|, q0 = normal + cubeS0·right + cubeT0·down
    glm::vec3 direction0{0.0f};   ///< d0 = q0 / |q0|
    float sqrtG0 = 0.0f;          ///< √(1 − e²·d0z²)
    float primeVertical0 = 0.0f;  ///< N0 = a / √g0
    glm::vec3 originFromCamera{
        0.0f};  ///< S(d0) − camera, the one planet-sized difference, in double
};

/// The frame of patch `id` with its reference point at patch coordinates (u0, v0) in [0, 1]²,
/// for a camera at ECEF `camera`.
PatchSurfaceFrame makePatchSurfaceFrame(const GlobePatchId& id, double u0, double v0,
                                        const glm::dvec3& camera);

/// The patch coordinates (u, v) in [0, 1]² of the camera's nadir clamped to the patch, from
/// `cameraUp`, the ellipsoid normal at the camera (Wgs84::upAt): the reference point that
/// keeps the vertices near the camera near O.
glm::dvec2 nearestPatchCoordinates(const GlobePatchId& id, const glm::dvec3& cameraUp);

/// The camera-relative position of patch coordinates (u, v) at height h, in float only.
glm::vec3 cameraRelativePosition(const PatchSurfaceFrame& frame, float u, float v, float height);

/// (O − camera) + S(d) − S(d0) + h·d for d = d0 + Δd, in float from small quantities:
/// N·M·Δd + (N − N0)·M·d0 (the header's derivation). What a face patch's and a native tile's
/// placement (NativeOffset.h) share once each has its Δd.
glm::vec3 surfaceOffsetFromDirection(const glm::vec3& originFromCamera, const glm::vec3& direction0,
                                     float sqrtG0, const glm::vec3& deltaDirection, float height);

}  // namespace terrain::globe
