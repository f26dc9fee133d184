// ReferenceRenderer: finest-level tiles culled against the frustum, uploaded a batch at a
// time into a texture array and drawn as instances of one grid of indexed triangles.
#include "terrain/runtime/ReferenceRenderer.h"

#include "terrain/base/Assert.h"
#include "terrain/gl/ReversedZScope.h"
#include "terrain/runtime/ProgramBuilder.h"
#include "terrain/runtime/TerrainFrameUniforms.h"

#include <epoxy/gl.h>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace terrain::runtime {

Result<ReferenceRenderer> ReferenceRenderer::create(const io::PyramidLayout& layout) {
    ProgramBuilder builder("reference");
    builder.stage("reference.vert").stage("reference.frag");
    auto program = builder.build();
    if (!program) return program.error();

    ReferenceRenderer r;
    r.m_program = std::move(program).value();
    r.m_tileQuads = std::min(layout.patchQuads(), kMaxTileQuads);
    const int quads = r.m_tileQuads;
    r.m_grid = SampleGrid::create(quads, "reference grid");
    r.m_instances = gl::Buffer::create(sizeof(TileInstance) * kBatchTiles, GL_DYNAMIC_STORAGE_BIT,
                                       "reference tiles");
    auto heights = gl::Texture::create2DArray(
        {.internalFormat = GL_R32F, .width = quads + 3, .height = quads + 3, .layers = kBatchTiles},
        "reference tile heights");
    if (!heights) return heights.error();
    r.m_heights = std::move(heights).value();
    r.m_heights.setSampling(GL_NEAREST, GL_NEAREST, GL_CLAMP_TO_EDGE);
    r.m_staging.reserve(kBatchTiles);
    r.m_tileScratch.resize(static_cast<std::size_t>(quads + 3) *
                           static_cast<std::size_t>(quads + 3));
    return r;
}

Result<ReferenceDrawStats> ReferenceRenderer::draw(const Camera& camera,
                                                   FullResolutionSurface& surface,
                                                   const ReferenceStyle& style) {
    const TerrainGeometry& geometry = surface.geometry();
    const io::PyramidLayout& layout = surface.layout();
    TERRAIN_ASSERT(std::min(layout.patchQuads(), kMaxTileQuads) == m_tileQuads,
                   "ReferenceRenderer: created for another patch size");
    const int finest = layout.finestLevel();
    const int quads = m_tileQuads;
    const int tilesPerPatch = layout.patchQuads() / quads;
    const int tileSide = quads + 3;
    const auto recordSide = static_cast<std::size_t>(layout.tileSamples());

    // Placed and shaded as the LOD draw, so both draws are equally exact and alike.
    const glm::dvec2 spacing = geometry.sampleSpacing();
    const glm::dvec2 anchor = setCameraFrameUniforms(m_program, camera, geometry);
    setShadingUniforms(m_program, geometry, style.skyColor, style.fogDensityPerM);
    m_program.setUniform("u_tileSamples", quads + 1);

    const gl::ReversedZScope reversedZ;
    const Frustum frustum = camera.frustum();
    const glm::dvec2 tileSizeM = spacing * static_cast<double>(quads);
    ReferenceDrawStats stats;
    m_staging.clear();
    Status status;
    for (std::int64_t py = 0; py < layout.patchesY(finest) && status; ++py) {
        for (std::int64_t px = 0; px < layout.patchesX(finest) && status; ++px) {
            const io::PatchId id{finest, px, py};
            auto info = surface.info(id);
            if (!info) {
                status = info.error();
                break;
            }
            const glm::dvec2 patchNorthWest = geometry.patchNorthWest(id);
            const io::PatchRecord* record = nullptr;
            for (int ty = 0; ty < tilesPerPatch; ++ty) {
                for (int tx = 0; tx < tilesPerPatch; ++tx) {
                    // Tiles wholly beyond the DEM (in the last patches' overhang) draw nothing.
                    if (layout.patchOriginX(id) + tx * quads > layout.rasterWidth() - 1 ||
                        layout.patchOriginY(id) + ty * quads > layout.rasterHeight() - 1) {
                        continue;
                    }
                    const glm::dvec2 nw =
                        patchNorthWest + glm::dvec2(tx * tileSizeM.x, -ty * tileSizeM.y);
                    const Aabb box{.min = {nw.x, nw.y - tileSizeM.y,
                                           static_cast<double>(info.value().minHeight)},
                                   .max = {nw.x + tileSizeM.x, nw.y,
                                           static_cast<double>(info.value().maxHeight)}};
                    if (!frustum.intersects(box)) continue;
                    if (record == nullptr) {
                        auto read = surface.patch(id);
                        if (!read) {
                            status = read.error();
                            break;
                        }
                        record = read.value();
                    }
                    // The tile's samples plus a one-sample apron, cut from the patch's tile
                    // (which has its own apron, so every tile has neighbours for normals).
                    const std::size_t firstColumn =
                        static_cast<std::size_t>(tx) * static_cast<std::size_t>(quads);
                    const std::size_t firstRow =
                        static_cast<std::size_t>(ty) * static_cast<std::size_t>(quads);
                    for (int row = 0; row < tileSide; ++row) {
                        std::memcpy(m_tileScratch.data() + static_cast<std::size_t>(row * tileSide),
                                    record->heights.data() +
                                        (firstRow + static_cast<std::size_t>(row)) * recordSide +
                                        firstColumn,
                                    static_cast<std::size_t>(tileSide) * sizeof(float));
                    }
                    const int layer = static_cast<int>(m_staging.size());
                    m_heights.upload(
                        {.x = 0, .y = 0, .layer = layer, .width = tileSide, .height = tileSide},
                        GL_RED, GL_FLOAT, std::as_bytes(std::span(m_tileScratch)));
                    const double originX =
                        static_cast<double>(layout.patchOriginX(id) + tx * quads) - anchor.x;
                    const double originY =
                        static_cast<double>(layout.patchOriginY(id) + ty * quads) - anchor.y;
                    m_staging.push_back({{static_cast<float>(originX), static_cast<float>(originY),
                                          static_cast<float>(layer), 0.0f}});
                    ++stats.tiles;
                    if (static_cast<int>(m_staging.size()) == kBatchTiles) {
                        submitBatch(kBatchTiles);
                        ++stats.batches;
                        m_staging.clear();
                    }
                }
                if (!status) break;
            }
        }
    }
    if (status && !m_staging.empty()) {
        submitBatch(static_cast<int>(m_staging.size()));
        ++stats.batches;
    }
    m_staging.clear();
    if (!status) return status.error();
    stats.triangles =
        stats.tiles * 2 * static_cast<std::uint64_t>(quads) * static_cast<std::uint64_t>(quads);
    return stats;
}

void ReferenceRenderer::submitBatch(int tiles) {
    m_instances.upload(0,
                       std::as_bytes(std::span(m_staging).first(static_cast<std::size_t>(tiles))));
    m_grid.draw(m_program, m_heights, m_instances, tiles);
}

}  // namespace terrain::runtime
