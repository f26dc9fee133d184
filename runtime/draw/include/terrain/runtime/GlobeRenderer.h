// GlobeRenderer: draws the LOD's patches of a globe pyramid on the WGS84 ellipsoid in ONE
// instanced draw of GL_PATCHES, as TerrainRenderer does on the plane: per instance one quad
// patch primitive per tessellation block and the skirts (the same vertex stage), with
// globe.tesc choosing per-edge factors from the block errors and globe.tese placing every
// vertex camera-relative in float from a per-patch reference point computed in double
// (globe_patches.glsl; io/globe SurfaceOffset.h). Bare patches (no data) are the ellipsoid.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/cache/GpuTilePool.h"
#include "terrain/gl/Buffer.h"
#include "terrain/gl/Program.h"
#include "terrain/gl/Query.h"
#include "terrain/gl/VertexArray.h"
#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/GlobeInstance.h"
#include "terrain/runtime/PatchDraw.h"
#include "terrain/runtime/TerrainRenderer.h"

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace terrain::runtime {

/// The sun of a globe frame: high over the camera's shoulder, so the place flown over is lit
/// wherever it is (unit length, ECEF axes).
glm::dvec3 globeSunDirection(const Camera& camera);

/// The heights the hypsometric tint spans: the data's, sea level included (bare patches are
/// at 0).
std::array<float, 2> globeHeightRange(const io::PyramidManifest& manifest);

/// Render thread only; draws into the framebuffer bound by the caller and puts back the GL
/// state it sets, as TerrainRenderer.
class GlobeRenderer {
public:
    static Result<GlobeRenderer> create(const io::PyramidManifest& manifest, int maxInstances);

    /// Draws `patches` (data patches resident in `pool` on their layer) seen by `camera`
    /// (ECEF position). Depth must be cleared to 0 (reversed Z). errorPx is ε of the
    /// fine LOD; fog, wireframe, skirts, block culling and debug views as on the plane.
    TerrainDrawStats draw(const Camera& camera, const cache::GpuTilePool& pool,
                          std::span<const PatchDraw> patches, const TerrainStyle& style,
                          double errorPx);

private:
    void setUniforms(const Camera& camera, const TerrainStyle& style, double errorPx);

    gl::Program m_program;
    gl::VertexArray m_vertexArray;
    gl::Buffer m_instances;
    gl::Query m_primitivesQuery;
    gl::Query m_timeQuery;
    std::vector<GlobeInstance> m_staging;
    int m_maxInstances = 0;
    int m_blocksPerSide = 0;
    int m_blockQuads = 0;
    int m_patchQuads = 0;
    std::array<float, 2> m_heightRange{0.0f, 1.0f};
};

}  // namespace terrain::runtime
