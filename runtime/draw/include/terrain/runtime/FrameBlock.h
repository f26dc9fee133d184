// FrameBlock: the per-frame parameters of the patch draws as the C++ struct a renderer uploads
// into its uniform buffer, expanded from the one member list the shaders expand too
// (shaders/FrameBlockLayout.h, terrain_frame.glsl), and the helpers that fill its parts that
// every patch draw shares: the camera, the tessellation grid, the look. Where the surface
// lies relative to the camera (the plane's anchor and DEM extent, the sun) is
// SurfacePlacement's part.
#pragma once

#include "FrameBlockLayout.h"
#include "terrain/gl/Buffer.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/TerrainStyle.h"

#include <array>
#include <cstdint>

namespace terrain::runtime {

#define TERRAIN_CPP_MAT4(name) std::array<float, 16> name{};
#define TERRAIN_CPP_VEC4(name) std::array<float, 4> name{};
#define TERRAIN_CPP_IVEC4(name) std::array<std::int32_t, 4> name{};
#define TERRAIN_CPP_VEC4_ARRAY(name, count) std::array<std::array<float, 4>, count> name{};

/// std140: every member a vec4, ivec4, mat4 (column-major) or array of vec4.
struct alignas(16) FrameBlock {
    TERRAIN_FRAME_BLOCK_MEMBERS(TERRAIN_CPP_MAT4, TERRAIN_CPP_VEC4, TERRAIN_CPP_IVEC4,
                                TERRAIN_CPP_VEC4_ARRAY)
};
static_assert(sizeof(FrameBlock) == 2 * 64 + 5 * 16 + 14 * 16, "FrameBlock: std140 layout");

/// The camera's part, in float from double: the drawn camera's view-projection and frustum
/// (relative to it), the viewport and near plane, ε; the camera whose view decides the
/// tessellation (`lodCamera`, the drawn one unless the style says otherwise) and how far the
/// drawn one is from it; the most pixels a metre can cover at unit distance.
void setCameraFrame(FrameBlock& block, const Camera& camera, const Camera& lodCamera,
                    double errorPx);

/// The tessellation grid of an instance: blocks per patch side, quads a block side and a
/// patch side, the fixed simplification d (−1: error-driven).
void setTessellation(FrameBlock& block, int blocksPerSide, int blockQuads, int patchQuads,
                     int fixedSimplification);

/// The style's part: block culling, the debug view, the sky and the fog.
void setLook(FrameBlock& block, const TerrainStyle& style);

/// A uniform buffer holding one FrameBlock, bound at TERRAIN_BINDING_FRAME_BLOCK by the
/// draw (InstancedPatchDraw). Render thread only.
class FrameBlockBuffer {
public:
    static FrameBlockBuffer create(const std::string& label);
    void upload(const FrameBlock& block);
    const gl::Buffer& buffer() const { return m_buffer; }

private:
    gl::Buffer m_buffer;
};

}  // namespace terrain::runtime
