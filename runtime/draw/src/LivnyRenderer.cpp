// LivnyRenderer: instance records and one instanced draw of four tile primitives a patch.
#include "terrain/runtime/LivnyRenderer.h"

#include "InstancedPatchDraw.h"
#include "terrain/base/Assert.h"
#include "terrain/runtime/ProgramBuilder.h"
#include "terrain/runtime/TerrainFrameUniforms.h"

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
    TERRAIN_ASSERT(maxInstances >= 1);
    ProgramBuilder builder("livny2007");
    builder.stage("terrain.vert").stage("livny.tesc").stage("livny.tese").stage("terrain.frag");
    auto program = builder.build();
    if (!program) return program.error();
    auto primitives = gl::Query::create(gl::QueryKind::PrimitivesGenerated, "livny triangles");
    if (!primitives) return primitives.error();
    auto time = gl::Query::create(gl::QueryKind::TimeElapsed, "livny GPU time");
    if (!time) return time.error();
    LivnyRenderer r;
    r.m_program = std::move(program).value();
    r.m_primitivesQuery = std::move(primitives).value();
    r.m_timeQuery = std::move(time).value();
    r.m_vertexArray = gl::VertexArray::create("livny tiles (attribute-less)");
    r.m_instances =
        gl::Buffer::create(sizeof(PatchInstanceRecord) * static_cast<std::size_t>(maxInstances),
                           GL_DYNAMIC_STORAGE_BIT, "livny patch instances");
    r.m_staging.reserve(static_cast<std::size_t>(maxInstances));
    r.m_maxInstances = maxInstances;
    r.m_patchQuads = layout.patchQuads();
    return r;
}

TerrainDrawStats LivnyRenderer::draw(const Camera& camera, const TerrainGeometry& geometry,
                                     const cache::GpuTilePool& pool,
                                     std::span<const PatchDraw> patches,
                                     const TerrainStyle& style) {
    TERRAIN_ASSERT(patches.size() <= static_cast<std::size_t>(m_maxInstances),
                   "LivnyRenderer: more patches than instances");
    if (patches.empty()) return {};
    const glm::dvec2 anchor = setCameraFrameUniforms(m_program, camera, geometry);
    writePatchInstanceRecords(geometry.layout(), pool, patches, anchor, m_staging);
    m_instances.upload(0, std::as_bytes(std::span(m_staging)));

    // terrain.vert's 2 × 2 "blocks" are the four tile primitives; livny.tesc makes each a
    // triangle on its edge.
    m_program.setUniform("u_blocksPerSide", 2);
    m_program.setUniform("u_blockQuads", m_patchQuads / 2);
    m_program.setUniform("u_errorPx", static_cast<float>(style.errorPx));
    m_program.setUniform("u_errorScale", static_cast<float>(camera.errorScale()));
    m_program.setUniform("u_innerScale", kInnerScale);
    setShadingUniforms(m_program, geometry, style.skyColor, style.fogDensityPerM);
    m_program.setUniform("u_debugView", static_cast<int>(style.debugView));
    return issueInstancedPatchDraw(pool,
                                   {.program = m_program,
                                    .vertexArray = m_vertexArray,
                                    .instances = m_instances,
                                    .verticesPerInstance = 4 * 4,
                                    .instanceCount = static_cast<int>(patches.size()),
                                    .wireframe = style.wireframe,
                                    .primitivesQuery = style.measure ? &m_primitivesQuery : nullptr,
                                    .timeQuery = style.measure ? &m_timeQuery : nullptr});
}

}  // namespace terrain::runtime
