// TerrainRenderer: draws the selected patches from the GPU tile pool in ONE instanced
// draw of GL_PATCHES (Yusov & Shevtsov 2011, §5 "Implementation Details"): one instance
// per patch, one quad patch primitive per tessellation block, heights from the patch's
// texture-array layer. Per-instance data lives in a storage buffer written once a frame.
#pragma once

#include "terrain/cache/GpuTilePool.h"
#include "terrain/gl/Buffer.h"
#include "terrain/gl/Program.h"
#include "terrain/gl/VertexArray.h"
#include "terrain/io/PyramidLayout.h"
#include "terrain/io/Result.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/PatchSelection.h"
#include "terrain/runtime/TerrainGeometry.h"

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace terrain::runtime {

struct TerrainStyle {
    std::array<float, 3> skyColor{0.72f, 0.80f, 0.90f};
    float fogDensityPerM = 0.0f;  ///< 0: no fog
    bool colorByLevel = false;
    /// Segments per block edge, a power of two ≤ blockQuads (blockQuads: every sample).
    int tessFactor = 0;  ///< 0 means blockQuads
};

struct TerrainDrawStats {
    int drawCalls = 0;
    int instances = 0;
};

/// Render thread only; draws into the framebuffer bound by the caller. Holds its own GL
/// objects; the depth test, reversed-Z clip control and program state it sets are put
/// back to GL's defaults after each draw.
class TerrainRenderer {
public:
    /// `maxInstances` bounds the patches of one draw (the pool's capacity is enough).
    static io::Result<TerrainRenderer> create(const io::PyramidLayout& layout, int maxInstances);

    /// Draws `patches` (every one resident in `pool`, TERRAIN_ASSERT) seen by `camera`:
    /// prepare() then submit(). Depth must be cleared to 0 (reversed Z).
    TerrainDrawStats draw(const Camera& camera, const TerrainGeometry& geometry,
                          const cache::GpuTilePool& pool, std::span<const PatchDraw> patches,
                          const TerrainStyle& style);

    /// The CPU half of draw(): writes the instance records (camera-relative, from double)
    /// into the instance buffer and sets the uniforms. Allocates nothing.
    void prepare(const Camera& camera, const TerrainGeometry& geometry,
                 const cache::GpuTilePool& pool, std::span<const PatchDraw> patches,
                 const TerrainStyle& style);
    /// The GL half: binds the pool's textures and issues the one instanced draw of what
    /// prepare() wrote. (Drivers may allocate inside the draw call: Mesa's tessellator does.)
    TerrainDrawStats submit(const cache::GpuTilePool& pool);

private:
    struct alignas(16) PatchInstance {  // std430 layout of terrain_patches.glsl
        std::array<float, 4> northWestAndSize;
        std::array<std::int32_t, 4> layerLevel;
    };
    static_assert(sizeof(PatchInstance) == 32);

    gl::Program m_program;
    gl::VertexArray m_vertexArray;
    gl::Buffer m_instances;
    std::vector<PatchInstance> m_staging;  // capacity maxInstances
    int m_maxInstances = 0;
    int m_preparedInstances = 0;
    int m_blocksPerSide = 0;
    int m_blockQuads = 0;
    int m_patchQuads = 0;
};

}  // namespace terrain::runtime
