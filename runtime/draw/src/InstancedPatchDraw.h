// InstancedPatchDraw: the GL half every patch renderer shares (TerrainRenderer on either
// surface, the comparison methods' renderers): bind the pool's texture arrays, the frame block
// and the instance buffer, issue ONE instanced draw (of GL_PATCHES, or of an indexed triangle
// grid), measure it if asked, and put GL's state back. The renderers differ only in their
// programs.
#pragma once

#include "terrain/cache/GpuTilePool.h"
#include "terrain/gl/Buffer.h"
#include "terrain/gl/Program.h"
#include "terrain/gl/Query.h"
#include "terrain/gl/VertexArray.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/TerrainStyle.h"

#include <array>

namespace terrain::runtime {

struct InstancedPatchDraw {
    const gl::Program& program;
    const gl::VertexArray& vertexArray;
    const gl::Buffer& frame;  ///< the FrameBlock, bound at TERRAIN_BINDING_FRAME_BLOCK
    const gl::Buffer& instances;
    /// Bound at TERRAIN_BINDING_SHADING_TILES when the program reads them (ShadingTiles.h).
    const gl::Buffer* shadingTiles = nullptr;
    const gl::Buffer* tessFactors = nullptr;  ///< bound for TERRAIN_DEBUG_TESS_FACTORS
    int verticesPerInstance = 0;  ///< GL_PATCHES of 4 vertices each (indexCount 0)
    /// > 0: indexed GL_TRIANGLES from the vertex array's index buffer instead (a draw
    /// without tessellation: CDLOD's grids).
    int indexCount = 0;
    int instanceCount = 0;
    bool wireframe = false;
    /// Measures with these queries (GL_PRIMITIVES_GENERATED, GL_TIME_ELAPSED) and waits.
    gl::Query* primitivesQuery = nullptr;
    gl::Query* timeQuery = nullptr;
};

/// The simplification d of a fixed factor: the factor rounded down to a power of two in
/// [max(1, blockQuads >> 4), blockQuads] is blockQuads >> d, with d ≤ 4 so the block
/// errors λ(d) still bound the skirts' drop. −1 (error-driven) for factor ≤ 0.
int fixedSimplification(int factor, int blockQuads);

/// The camera's frustum planes (left, right, bottom, top, near) relative to the camera, xyzw
/// each: the offsets are computed in double before the cast (the world planes' offsets are
/// planet-sized, the relative ones are not).
std::array<float, 20> relativeFrustumPlanes(const Camera& camera);

TerrainDrawStats issueInstancedPatchDraw(const cache::GpuTilePool& pool,
                                         const InstancedPatchDraw& draw);

}  // namespace terrain::runtime
