// LivnyRenderer: instance records and one instanced draw of four tile primitives a patch.
#include "terrain/runtime/LivnyRenderer.h"

#include "InstancedPatchDraw.h"

#include <epoxy/gl.h>

namespace terrain::runtime {
namespace {

// A tile at resolution r is, in the paper, the part of an r × r grid between the patch edge
// and the centre: r² / 2 triangles and about r² / 4 vertices. The tessellator's triangle
// domain at inner level m has 3 m² / 2 triangles and about 3 m² / 4 vertices, so m = r / √3
// gives the tile the paper's counts of both.
constexpr float kInnerScale = 0.57735027f;

}  // namespace

Result<LivnyRenderer> LivnyRenderer::create(const io::PyramidLayout& layout, int maxInstances) {
    auto draw = MethodPatchDraw::create(
        "livny2007", {"terrain.vert", "livny.tesc", "livny.tese", "terrain.frag"}, maxInstances);
    if (!draw) return draw.error();
    LivnyRenderer r;
    r.m_draw = std::move(draw).value();
    r.m_patchQuads = layout.patchQuads();
    return r;
}

TerrainDrawStats LivnyRenderer::draw(const Camera& camera, const TerrainGeometry& geometry,
                                     const cache::GpuTilePool& pool,
                                     std::span<const PatchDraw> patches, const TerrainStyle& style,
                                     double errorPx) {
    if (patches.empty()) return {};
    m_draw.prepare(camera, geometry, pool, patches, style, errorPx);
    // terrain.vert's 2 × 2 "blocks" are the four tile primitives; livny.tesc makes each a
    // triangle on its edge.
    setTessellation(m_draw.frame, 2, m_patchQuads / 2, m_patchQuads, -1);
    m_draw.uploadFrame();
    gl::Program& program = m_draw.program;
    program.setUniform("u_innerScale", kInnerScale);
    return issueInstancedPatchDraw(pool, {.program = program,
                                          .vertexArray = m_draw.vertexArray,
                                          .frame = m_draw.frameBuffer.buffer(),
                                          .instances = m_draw.instances,
                                          .verticesPerInstance = 4 * 4,
                                          .instanceCount = static_cast<int>(patches.size()),
                                          .wireframe = style.wireframe,
                                          .primitivesQuery = m_draw.primitivesIf(style),
                                          .timeQuery = m_draw.timeIf(style)});
}

}  // namespace terrain::runtime
