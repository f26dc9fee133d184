// CdlodRenderer: one indexed grid, instanced once a patch.
#include "terrain/runtime/CdlodRenderer.h"

#include "Bindings.h"
#include "terrain/base/Assert.h"
#include "terrain/gl/PolygonModeScope.h"
#include "terrain/gl/ReversedZScope.h"
#include "terrain/runtime/ProgramBuilder.h"
#include "terrain/runtime/TerrainFrameUniforms.h"

#include <epoxy/gl.h>

#include <cstdint>

namespace terrain::runtime {

Result<CdlodRenderer> CdlodRenderer::create(const io::PyramidLayout& layout, int maxInstances) {
    TERRAIN_ASSERT(maxInstances >= 1);
    ProgramBuilder builder("cdlod");
    builder.stage("cdlod.vert").stage("terrain.frag");
    auto program = builder.build();
    if (!program) return program.error();
    auto primitives = gl::Query::create(gl::QueryKind::PrimitivesGenerated, "cdlod triangles");
    if (!primitives) return primitives.error();
    auto time = gl::Query::create(gl::QueryKind::TimeElapsed, "cdlod GPU time");
    if (!time) return time.error();

    // The grid of the patch's samples, each quad split along its north-west–south-east
    // diagonal.
    const int quads = layout.patchQuads();
    const auto samples = static_cast<std::uint32_t>(quads + 1);
    std::vector<std::uint32_t> indices;
    indices.reserve(static_cast<std::size_t>(quads) * static_cast<std::size_t>(quads) * 6);
    for (std::uint32_t j = 0; j < static_cast<std::uint32_t>(quads); ++j) {
        for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(quads); ++i) {
            const std::uint32_t nw = j * samples + i, ne = nw + 1, sw = nw + samples, se = sw + 1;
            indices.insert(indices.end(), {nw, ne, se, nw, se, sw});
        }
    }
    CdlodRenderer r;
    r.m_program = std::move(program).value();
    r.m_primitivesQuery = std::move(primitives).value();
    r.m_timeQuery = std::move(time).value();
    r.m_indices = gl::Buffer::createFrom(std::span<const std::uint32_t>(indices), 0, "cdlod grid");
    r.m_indexCount = static_cast<int>(indices.size());
    r.m_vertexArray = gl::VertexArray::create("cdlod grid (attribute-less)");
    r.m_vertexArray.setIndexBuffer(r.m_indices);
    r.m_instances =
        gl::Buffer::create(sizeof(PatchInstanceRecord) * static_cast<std::size_t>(maxInstances),
                           GL_DYNAMIC_STORAGE_BIT, "cdlod patch instances");
    r.m_staging.reserve(static_cast<std::size_t>(maxInstances));
    r.m_maxInstances = maxInstances;
    r.m_gridQuads = quads;
    return r;
}

TerrainDrawStats CdlodRenderer::draw(const Camera& camera, const TerrainGeometry& geometry,
                                     const cache::GpuTilePool& pool,
                                     std::span<const PatchDraw> patches,
                                     const TerrainStyle& style) {
    TERRAIN_ASSERT(patches.size() <= static_cast<std::size_t>(m_maxInstances),
                   "CdlodRenderer: more patches than instances");
    if (patches.empty()) return {};
    const glm::dvec2 anchor = setCameraFrameUniforms(m_program, camera, geometry);
    writePatchInstanceRecords(geometry.layout(), pool, patches, anchor, m_staging);
    m_instances.upload(0, std::as_bytes(std::span(m_staging)));
    m_program.setUniform("u_gridQuads", m_gridQuads);
    m_program.setUniform("u_rangePerMetre",
                         static_cast<float>(camera.errorScale() / style.errorPx));
    m_program.setUniform("u_morphStartRatio", kMorphStartRatio);
    setShadingUniforms(m_program, geometry, style.skyColor, style.fogDensityPerM);
    m_program.setUniform("u_debugView", static_cast<int>(style.debugView));

    const auto instances = static_cast<GLsizei>(patches.size());
    TerrainDrawStats stats{.drawCalls = 1, .instances = static_cast<int>(instances)};
    {
        const gl::ReversedZScope reversedZ;
        const gl::PolygonModeScope polygonMode(style.wireframe);
        glUseProgram(m_program.id());
        glBindVertexArray(m_vertexArray.id());
        glBindTextureUnit(TERRAIN_BINDING_HEIGHTS, pool.heights().id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TERRAIN_BINDING_PATCH_INSTANCES,
                         m_instances.id());
        if (style.measure) {
            m_primitivesQuery.begin();
            m_timeQuery.begin();
        }
        glDrawElementsInstanced(GL_TRIANGLES, m_indexCount, GL_UNSIGNED_INT, nullptr, instances);
        if (style.measure) {
            m_timeQuery.end();
            m_primitivesQuery.end();
            stats.triangles = m_primitivesQuery.waitResult();
            stats.gpuMs = static_cast<double>(m_timeQuery.waitResult()) * 1e-6;
        }
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TERRAIN_BINDING_PATCH_INSTANCES, 0);
        glBindTextureUnit(TERRAIN_BINDING_HEIGHTS, 0);
        glBindVertexArray(0);
        glUseProgram(0);
    }
    return stats;
}

}  // namespace terrain::runtime
