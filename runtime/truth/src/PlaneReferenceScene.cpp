// PlaneReferenceScene: finest-level tiles culled against the frustum, cut from their patches
// with an apron and added to the batch.
#include "terrain/runtime/PlaneReferenceScene.h"

#include "terrain/runtime/ShadingTiles.h"
#include "terrain/runtime/SurfacePlacement.h"

#include <algorithm>
#include <array>
#include <cstring>

namespace terrain::runtime {

PlaneReferenceScene::PlaneReferenceScene(FullResolutionSurface& surface)
    : m_surface(surface), m_tileQuads(std::min(surface.layout().patchQuads(), kMaxTileQuads)) {
    m_tileScratch.resize(static_cast<std::size_t>(tileSamples()) *
                         static_cast<std::size_t>(tileSamples()));
}

void PlaneReferenceScene::beginFrame(const Camera& camera, FrameBlock& block) {
    PlanePlacement placement(m_surface.geometry());
    placement.beginFrame(camera, block);
    // The anchor the placement chose: the DEM sample at or before the camera.
    m_anchor = glm::floor(m_surface.geometry().sampleOfWorld(camera.position.x, camera.position.y));
}

namespace {

// A tile's key in a batch (unique in a draw): its level, patch, and which window of it.
std::uint64_t windowKey(const io::PatchId& id, int windowX, int windowY) {
    return (static_cast<std::uint64_t>(id.level) << 58) ^
           (static_cast<std::uint64_t>(id.y) << 38) ^ (static_cast<std::uint64_t>(id.x) << 16) ^
           (static_cast<std::uint64_t>(windowY) << 8) ^ static_cast<std::uint64_t>(windowX);
}

}  // namespace

Result<std::span<const float>> PlaneReferenceScene::cutWindow(const io::PatchId& id,
                                                              int windowX, int windowY) {
    // The window's samples plus a one-sample apron, cut from the patch's tile (which has its
    // own apron, so every window has neighbours for normals).
    auto read = m_surface.patch(id);
    if (!read) return read.error();
    const io::PatchRecord& record = *read.value();
    const int tileSide = tileSamples();
    const auto recordSide = static_cast<std::size_t>(m_surface.layout().tileSamples());
    const auto firstColumn = static_cast<std::size_t>(windowX) * static_cast<std::size_t>(m_tileQuads);
    const auto firstRow = static_cast<std::size_t>(windowY) * static_cast<std::size_t>(m_tileQuads);
    for (int row = 0; row < tileSide; ++row) {
        std::memcpy(m_tileScratch.data() + static_cast<std::size_t>(row * tileSide),
                    record.heights.data() + (firstRow + static_cast<std::size_t>(row)) * recordSide +
                        firstColumn,
                    static_cast<std::size_t>(tileSide) * sizeof(float));
    }
    return std::span<const float>(m_tileScratch);
}

Result<bool> PlaneReferenceScene::addInstances(const Camera& camera, ReferenceBatch& batch,
                                               std::uint64_t) {
    const TerrainGeometry& geometry = m_surface.geometry();
    const io::PyramidLayout& layout = m_surface.layout();
    const int finest = layout.finestLevel();
    const int quads = m_tileQuads;
    const int tilesPerPatch = layout.patchQuads() / quads;
    const Frustum frustum = camera.frustum();
    const glm::dvec2 tileSizeM = geometry.sampleSpacing() * static_cast<double>(quads);
    for (std::int64_t py = 0; py < layout.patchesY(finest); ++py) {
        for (std::int64_t px = 0; px < layout.patchesX(finest); ++px) {
            const io::PatchId id{finest, px, py};
            auto info = m_surface.info(id);
            if (!info) return info.error();
            const glm::dvec2 patchNorthWest = geometry.patchNorthWest(id);
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
                    // Each window is drawn once a frame: its key need only be unique in it.
                    auto layer = batch.layerOf(windowKey(id, tx, ty),
                                               [&] { return cutWindow(id, tx, ty); });
                    if (!layer) return layer.error();
                    // The tiles above it for the footprint-filtered normals, as the LOD draw
                    // reads them (ShadingTiles.h): of each, the window of kMaxTileQuads its
                    // samples lie in (they span at most that many: they never straddle two).
                    std::array<ShadingTile, kShadingAncestors> shading;
                    Status read;
                    shadingTilesOf(
                        {.id = id,
                         .texelOffset = {static_cast<float>(tx * quads),
                                         static_cast<float>(ty * quads)},
                         .texelStep = 1.0f,
                         .layer = layer.value()},
                        layout.patchQuads(),
                        [&](AncestorTile& a) -> std::optional<int> {
                            if (!read) return {};
                            const int windowX = static_cast<int>(a.texelOffset[0]) / quads;
                            const int windowY = static_cast<int>(a.texelOffset[1]) / quads;
                            auto window = batch.layerOf(windowKey(a.id, windowX, windowY), [&] {
                                return cutWindow(a.id, windowX, windowY);
                            });
                            if (!window) {
                                read = window.error();
                                return {};
                            }
                            a.texelOffset[0] -= static_cast<float>(windowX * quads);
                            a.texelOffset[1] -= static_cast<float>(windowY * quads);
                            return window.value();
                        },
                        shading);
                    if (!read) return read.error();
                    // Double → float only after subtracting the anchor.
                    const double originX =
                        static_cast<double>(layout.patchOriginX(id) + tx * quads) - m_anchor.x;
                    const double originY =
                        static_cast<double>(layout.patchOriginY(id) + ty * quads) - m_anchor.y;
                    PatchInstance tile;
                    tile.placement0 = {static_cast<float>(originX), static_cast<float>(originY),
                                       1.0f, 0.0f};
                    tile.texelMap = {0.0f, 0.0f, 1.0f, 0.0f};  // its own window, sample for sample
                    tile.layerLevel = {layer.value(), finest, 0, 0};
                    batch.add(tile, shading);
                }
            }
        }
    }
    return true;
}

}  // namespace terrain::runtime
