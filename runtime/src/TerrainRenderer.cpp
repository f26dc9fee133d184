// TerrainRenderer: camera-relative instance records (double → float after subtracting the
// camera), then one glDrawArraysInstanced of blocks² · 4 patch vertices.
#include "terrain/runtime/TerrainRenderer.h"

#include "Bindings.h"
#include "terrain/io/Assert.h"
#include "terrain/runtime/ProgramBuilder.h"

#include <epoxy/gl.h>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>

namespace terrain::runtime {

io::Result<TerrainRenderer> TerrainRenderer::create(const io::PyramidLayout& layout,
                                                    int maxInstances) {
    TERRAIN_ASSERT(maxInstances >= 1);
    auto program = ProgramBuilder("terrain")
                       .stage("terrain.vert")
                       .stage("terrain.tesc")
                       .stage("terrain.tese")
                       .stage("terrain.frag")
                       .build();
    if (!program) return program.error();
    TerrainRenderer r;
    r.m_program = std::move(program).value();
    r.m_vertexArray = gl::VertexArray::create("terrain patches (attribute-less)");
    r.m_maxInstances = maxInstances;
    r.m_instances = gl::Buffer::create(sizeof(PatchInstance) * static_cast<std::size_t>(maxInstances),
                                       GL_DYNAMIC_STORAGE_BIT, "terrain patch instances");
    r.m_staging.reserve(static_cast<std::size_t>(maxInstances));
    r.m_blocksPerSide = layout.blocksPerSide();
    r.m_blockQuads = layout.blockQuads();
    r.m_patchQuads = layout.patchQuads();
    return r;
}

TerrainDrawStats TerrainRenderer::draw(const Camera& camera, const TerrainGeometry& geometry,
                                       const cache::GpuTilePool& pool,
                                       std::span<const PatchDraw> patches,
                                       const TerrainStyle& style) {
    prepare(camera, geometry, pool, patches, style);
    return submit(pool);
}

void TerrainRenderer::prepare(const Camera& camera, const TerrainGeometry& geometry,
                              const cache::GpuTilePool& pool, std::span<const PatchDraw> patches,
                              const TerrainStyle& style) {
    TERRAIN_ASSERT(patches.size() <= static_cast<std::size_t>(m_maxInstances),
                   "TerrainRenderer: more patches than instances");
    m_preparedInstances = static_cast<int>(patches.size());
    if (patches.empty()) return;
    m_staging.clear();
    for (const PatchDraw& p : patches) {
        TERRAIN_ASSERT(pool.isResident(p.id) && pool.layerOf(p.id) == p.layer,
                       "TerrainRenderer: drawing a patch that is not resident on its layer");
        const glm::dvec2 nw = geometry.patchNorthWest(p.id);
        const glm::dvec2 size = geometry.patchSize(p.id.level);
        m_staging.push_back(
            {{static_cast<float>(nw.x - camera.position.x), static_cast<float>(nw.y - camera.position.y),
              static_cast<float>(size.x), static_cast<float>(size.y)},
             {p.layer, p.id.level, 0, 0}});
    }
    m_instances.upload(0, std::as_bytes(std::span(m_staging)));

    const glm::mat4 viewProjection(camera.relativeViewProjection());
    const int tessFactor = style.tessFactor > 0 ? std::min(style.tessFactor, m_blockQuads)
                                                : m_blockQuads;
    m_program.setUniform("u_blocksPerSide", m_blocksPerSide);
    m_program.setUniform("u_blockQuads", m_blockQuads);
    m_program.setUniform("u_patchQuads", m_patchQuads);
    m_program.setUniform("u_tessFactor", static_cast<float>(tessFactor));
    m_program.setUniformMat4("u_viewProjection",
                             std::span<const float, 16>(glm::value_ptr(viewProjection), 16));
    m_program.setUniform("u_cameraHeightM", static_cast<float>(camera.position.z));
    m_program.setUniform("u_sunDirection", std::array<float, 3>{-0.5345f, 0.6414f, 0.5505f});
    m_program.setUniform("u_heightRangeM",
                         std::array<float, 2>{static_cast<float>(geometry.minHeight()),
                                              static_cast<float>(geometry.maxHeight())});
    m_program.setUniform("u_skyColor", style.skyColor);
    m_program.setUniform("u_fogDensityPerM", style.fogDensityPerM);
    m_program.setUniform("u_colorByLevel", style.colorByLevel ? 1 : 0);
}

TerrainDrawStats TerrainRenderer::submit(const cache::GpuTilePool& pool) {
    if (m_preparedInstances == 0) return {};
    // Reversed Z: depth = near / distance, cleared to 0, nearer is greater.
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
    glUseProgram(m_program.id());
    glBindVertexArray(m_vertexArray.id());
    glBindTextureUnit(TERRAIN_BINDING_HEIGHTS, pool.heights().id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TERRAIN_BINDING_PATCH_INSTANCES, m_instances.id());
    glPatchParameteri(GL_PATCH_VERTICES, 4);

    glDrawArraysInstanced(GL_PATCHES, 0, 4 * m_blocksPerSide * m_blocksPerSide,
                          static_cast<GLsizei>(m_preparedInstances));

    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TERRAIN_BINDING_PATCH_INSTANCES, 0);
    glBindTextureUnit(TERRAIN_BINDING_HEIGHTS, 0);
    glBindVertexArray(0);
    glUseProgram(0);
    glDepthFunc(GL_LESS);
    glDisable(GL_DEPTH_TEST);
    glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
    const int instances = m_preparedInstances;
    m_preparedInstances = 0;
    return {.drawCalls = 1, .instances = instances};
}

}  // namespace terrain::runtime
