// CdlodRenderer: one indexed grid, instanced once a patch.
#include "terrain/runtime/CdlodRenderer.h"

#include "Bindings.h"
#include "terrain/gl/PolygonModeScope.h"
#include "terrain/gl/ReversedZScope.h"

#include <epoxy/gl.h>

#include <cstdint>

namespace terrain::runtime {

Result<CdlodRenderer> CdlodRenderer::create(const io::PyramidLayout& layout, int maxInstances) {
    auto draw = MethodPatchDraw::create("cdlod", {"cdlod.vert", "terrain.frag"}, maxInstances);
    if (!draw) return draw.error();

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
    r.m_draw = std::move(draw).value();
    r.m_indices = gl::Buffer::createFrom(std::span<const std::uint32_t>(indices), 0, "cdlod grid");
    r.m_indexCount = static_cast<int>(indices.size());
    r.m_draw.vertexArray.setIndexBuffer(r.m_indices);
    r.m_gridQuads = quads;
    return r;
}

TerrainDrawStats CdlodRenderer::draw(const Camera& camera, const TerrainGeometry& geometry,
                                     const cache::GpuTilePool& pool,
                                     std::span<const PatchDraw> patches,
                                     const TerrainStyle& style) {
    if (patches.empty()) return {};
    m_draw.prepare(camera, geometry, pool, patches, style);
    gl::Program& program = m_draw.program;
    program.setUniform("u_gridQuads", m_gridQuads);
    program.setUniform("u_rangePerMetre", static_cast<float>(camera.errorScale() / style.errorPx));
    program.setUniform("u_morphStartRatio", kMorphStartRatio);

    const auto instances = static_cast<GLsizei>(patches.size());
    TerrainDrawStats stats{.drawCalls = 1, .instances = static_cast<int>(instances)};
    gl::Query* const primitives = m_draw.primitivesIf(style);
    gl::Query* const time = m_draw.timeIf(style);
    {
        const gl::ReversedZScope reversedZ;
        const gl::PolygonModeScope polygonMode(style.wireframe);
        glUseProgram(program.id());
        glBindVertexArray(m_draw.vertexArray.id());
        glBindTextureUnit(TERRAIN_BINDING_HEIGHTS, pool.heights().id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TERRAIN_BINDING_PATCH_INSTANCES,
                         m_draw.instances.id());
        if (primitives != nullptr) {
            primitives->begin();
            time->begin();
        }
        glDrawElementsInstanced(GL_TRIANGLES, m_indexCount, GL_UNSIGNED_INT, nullptr, instances);
        if (primitives != nullptr) {
            time->end();
            primitives->end();
            stats.triangles = primitives->waitResult();
            stats.gpuMs = static_cast<double>(time->waitResult()) * 1e-6;
        }
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TERRAIN_BINDING_PATCH_INSTANCES, 0);
        glBindTextureUnit(TERRAIN_BINDING_HEIGHTS, 0);
        glBindVertexArray(0);
        glUseProgram(0);
    }
    return stats;
}

}  // namespace terrain::runtime
