// GlobeInstance: one drawn globe patch as the GPU sees it (std430 GlobeInstance of
// shaders/globe_patches.glsl): the float reference frame of io/globe SurfaceOffset.h,
// computed in double for the camera, plus the patch's errors, layer, level and face. The
// renderer writes one per instance; GlobePrecisionTest feeds the same records to the same
// GLSL to hold the GPU's positions to a double-precision reference.
#pragma once

#include "terrain/runtime/Camera.h"
#include "terrain/runtime/PatchDraw.h"

#include <glm/vec3.hpp>

#include <array>
#include <cstdint>

namespace terrain::runtime {

struct alignas(16) GlobeInstance {
    std::array<float, 4> frame0;           ///< dα/du, u0, v0, α0
    std::array<float, 4> frame1;           ///< β0, tan α0, tan β0, 1/|q0|
    std::array<float, 4> direction0;       ///< d0, √g0
    std::array<float, 4> origin;           ///< O − camera, N0
    std::array<float, 4> errors;           ///< Err(P), skirt depth, min and max height
    std::array<float, 4> bareBlockErrors;  ///< λ(1..4) of a bare patch
    std::array<float, 4> spacing;          ///< metres per tile sample along s and t near O
    std::array<float, 4> texelMap;         ///< tile sample offset (xy), step, virtual (1) or not
    std::array<std::int32_t, 4> layerLevelFace;
};
static_assert(sizeof(GlobeInstance) == 144);

/// The record of `patch` for a camera at ECEF `camera` whose ellipsoid normal is `cameraUp`
/// (Wgs84::upAt), with its reference point at the camera's nadir clamped to the patch.
GlobeInstance makeGlobeInstance(const PatchDraw& patch, const glm::dvec3& camera,
                                const glm::dvec3& cameraUp, int patchQuads);

}  // namespace terrain::runtime
