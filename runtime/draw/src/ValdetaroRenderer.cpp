// ValdetaroRenderer: the tile texture, the instance records and the one instanced draw.
#include "terrain/runtime/ValdetaroRenderer.h"

#include "Bindings.h"
#include "InstancedPatchDraw.h"
#include "terrain/base/Assert.h"

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
    auto draw = MethodPatchDraw::create(
        "valdetaro2011", {"terrain.vert", "valdetaro.tesc", "valdetaro.tese", "terrain.frag"},
        maxInstances);
    if (!draw) return draw.error();
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
    r.m_draw = std::move(draw).value();
    r.m_tiles = std::move(texture).value();
    r.m_parameters = parameters;
    r.m_tileQuads = tiles.tileQuads;
    r.m_tilesPerPatch = layout.patchQuads() / tiles.tileQuads;
    return r;
}

TerrainDrawStats ValdetaroRenderer::draw(const Camera& camera, const TerrainGeometry& geometry,
                                         const cache::GpuTilePool& pool,
                                         std::span<const PatchDraw> patches,
                                         const TerrainStyle& style, double errorPx) {
    if (patches.empty()) return {};
    m_draw.prepare(camera, geometry, pool, patches, style, errorPx);
    setTessellation(m_draw.frame, m_tilesPerPatch, m_tileQuads, geometry.layout().patchQuads(), -1);
    m_draw.uploadFrame();
    const glm::dvec2 spacing = geometry.sampleSpacing();
    const double dMaxM =
        camera.errorScale() * std::min(spacing.x, spacing.y) / m_parameters.pixelsPerSampleAtDMax;
    gl::Program& program = m_draw.program;
    program.setUniform("u_hamGain", static_cast<float>(m_parameters.hamGain));
    program.setUniform("u_dMaxM", static_cast<float>(dMaxM));
    program.setUniform("u_maxFactor",
                       static_cast<float>(std::min(m_tileQuads, kValdetaroMaxFactor)));

    glBindTextureUnit(TERRAIN_BINDING_VALDETARO_TILES, m_tiles.id());
    const TerrainDrawStats stats =
        issueInstancedPatchDraw(pool, {.program = program,
                                       .vertexArray = m_draw.vertexArray,
                                       .frame = m_draw.frameBuffer.buffer(),
                                       .instances = m_draw.instances,
                                       .verticesPerInstance = 4 * m_tilesPerPatch * m_tilesPerPatch,
                                       .instanceCount = static_cast<int>(patches.size()),
                                       .wireframe = style.wireframe,
                                       .primitivesQuery = m_draw.primitivesIf(style),
                                       .timeQuery = m_draw.timeIf(style)});
    glBindTextureUnit(TERRAIN_BINDING_VALDETARO_TILES, 0);
    return stats;
}

}  // namespace terrain::runtime
