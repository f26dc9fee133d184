// ValdetaroRenderer: the tile texture, the instance records and the one instanced draw.
#include "terrain/runtime/ValdetaroRenderer.h"

#include "Bindings.h"
#include "InstancedPatchDraw.h"
#include "terrain/base/Assert.h"
#include "terrain/runtime/ProgramBuilder.h"
#include "terrain/runtime/TerrainFrameUniforms.h"

#include <epoxy/gl.h>

#include <algorithm>

namespace terrain::runtime {

Result<ValdetaroRenderer> ValdetaroRenderer::create(const io::PyramidLayout& layout,
                                                    int maxInstances,
                                                    const ValdetaroTileGrid& tiles,
                                                    const ValdetaroParameters& parameters) {
    TERRAIN_ASSERT(maxInstances >= 1 && tiles.tilesX > 0 && tiles.tilesY > 0);
    TERRAIN_ASSERT(tiles.tileQuads == valdetaroTileQuads(layout),
                   "ValdetaroRenderer: tiles of another pyramid");
    ProgramBuilder builder("valdetaro2011");
    builder.stage("terrain.vert")
        .stage("valdetaro.tesc")
        .stage("valdetaro.tese")
        .stage("terrain.frag");
    auto program = builder.build();
    if (!program) return program.error();
    auto primitives = gl::Query::create(gl::QueryKind::PrimitivesGenerated, "valdetaro triangles");
    if (!primitives) return primitives.error();
    auto time = gl::Query::create(gl::QueryKind::TimeElapsed, "valdetaro GPU time");
    if (!time) return time.error();
    auto texture = gl::Texture::create2D(
        {.internalFormat = GL_RGBA32F, .width = tiles.tilesX, .height = tiles.tilesY},
        "valdetaro tiles (HAM_max, h_max, base, position)");
    if (!texture) return texture.error();

    // §6.2's four channels; the position packed as column + 128 · row (exact in float).
    std::vector<std::array<float, 4>> texels;
    texels.reserve(tiles.tiles.size());
    for (const ValdetaroTile& t : tiles.tiles) {
        texels.push_back(
            {t.hamMax, t.heightMax, t.baseAtMax, static_cast<float>(t.maxColumn + 128 * t.maxRow)});
    }
    texture.value().upload({.width = tiles.tilesX, .height = tiles.tilesY}, GL_RGBA, GL_FLOAT,
                           std::as_bytes(std::span(texels)));
    texture.value().setSampling(GL_NEAREST, GL_NEAREST, GL_CLAMP_TO_EDGE);

    ValdetaroRenderer r;
    r.m_program = std::move(program).value();
    r.m_primitivesQuery = std::move(primitives).value();
    r.m_timeQuery = std::move(time).value();
    r.m_tiles = std::move(texture).value();
    r.m_vertexArray = gl::VertexArray::create("valdetaro tiles (attribute-less)");
    r.m_instances =
        gl::Buffer::create(sizeof(PatchInstanceRecord) * static_cast<std::size_t>(maxInstances),
                           GL_DYNAMIC_STORAGE_BIT, "valdetaro patch instances");
    r.m_staging.reserve(static_cast<std::size_t>(maxInstances));
    r.m_parameters = parameters;
    r.m_maxInstances = maxInstances;
    r.m_tileQuads = tiles.tileQuads;
    r.m_tilesPerPatch = layout.patchQuads() / tiles.tileQuads;
    return r;
}

TerrainDrawStats ValdetaroRenderer::draw(const Camera& camera, const TerrainGeometry& geometry,
                                         const cache::GpuTilePool& pool,
                                         std::span<const PatchDraw> patches,
                                         const TerrainStyle& style) {
    TERRAIN_ASSERT(patches.size() <= static_cast<std::size_t>(m_maxInstances),
                   "ValdetaroRenderer: more patches than instances");
    if (patches.empty()) return {};
    const io::PyramidLayout& layout = geometry.layout();
    const glm::dvec2 anchor = setCameraFrameUniforms(m_program, camera, geometry);
    writePatchInstanceRecords(layout, pool, patches, anchor, m_staging);
    m_instances.upload(0, std::as_bytes(std::span(m_staging)));

    const glm::dvec2 spacing = geometry.sampleSpacing();
    const double dMaxM =
        camera.errorScale() * std::min(spacing.x, spacing.y) / m_parameters.pixelsPerSampleAtDMax;
    m_program.setUniform("u_blocksPerSide", m_tilesPerPatch);
    m_program.setUniform("u_blockQuads", m_tileQuads);
    m_program.setUniform("u_viewportPx",
                         std::array<float, 2>{static_cast<float>(camera.viewportWidth),
                                              static_cast<float>(camera.viewportHeight)});
    m_program.setUniform("u_errorPx", static_cast<float>(style.errorPx));
    m_program.setUniform("u_hamGain", static_cast<float>(m_parameters.hamGain));
    m_program.setUniform("u_dMaxM", static_cast<float>(dMaxM));
    m_program.setUniform("u_maxFactor",
                         static_cast<float>(std::min(m_tileQuads, kValdetaroMaxFactor)));
    m_program.setUniform("u_cullBlocks", style.cullBlocks ? 1 : 0);
    setRelativeFrustumUniform(m_program, camera);
    setShadingUniforms(m_program, geometry, style.skyColor, style.fogDensityPerM);
    m_program.setUniform("u_debugView", static_cast<int>(style.debugView));

    glBindTextureUnit(TERRAIN_BINDING_VALDETARO_TILES, m_tiles.id());
    const TerrainDrawStats stats = issueInstancedPatchDraw(
        pool, {.program = m_program,
               .vertexArray = m_vertexArray,
               .instances = m_instances,
               .verticesPerInstance = 4 * m_tilesPerPatch * m_tilesPerPatch,
               .instanceCount = static_cast<int>(patches.size()),
               .wireframe = style.wireframe,
               .primitivesQuery = style.measure ? &m_primitivesQuery : nullptr,
               .timeQuery = style.measure ? &m_timeQuery : nullptr});
    glBindTextureUnit(TERRAIN_BINDING_VALDETARO_TILES, 0);
    return stats;
}

}  // namespace terrain::runtime
