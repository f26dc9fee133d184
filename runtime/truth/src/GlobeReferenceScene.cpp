// GlobeReferenceScene: the pyramid walked on disk down to the finest data, regions split for
// the ellipsoid's curvature only, added to the batch with their tiles.
#include "terrain/runtime/GlobeReferenceScene.h"

#include "terrain/base/Assert.h"
#include "terrain/globe/PatchBounds.h"
#include "terrain/globe/Wgs84.h"
#include "terrain/pyramid/GlobeLayout.h"
#include "terrain/runtime/GlobeFrustum.h"
#include "terrain/runtime/ShadingTiles.h"
#include "terrain/runtime/SurfacePlacement.h"

#include <fmt/format.h>

#include <algorithm>

namespace terrain::runtime {
namespace {

// The tiles read in one draw are kept for the regions after them (the quadrants of one
// patch, the parts a region splits into), up to this many.
constexpr std::size_t kKeptTiles = 16;

std::uint64_t tileKey(const io::PatchId& id) {
    return (std::uint64_t(id.level) << 58) | (std::uint64_t(id.y) << 29) | std::uint64_t(id.x);
}

}  // namespace

GlobeReferenceScene::GlobeReferenceScene(io::PyramidReader& pyramid)
    : m_pyramid(pyramid), m_layout(pyramid.layout()) {
    TERRAIN_ASSERT(pyramid.manifest().globe.has_value(),
                   "GlobeReferenceScene draws globe pyramids");
}

void GlobeReferenceScene::beginFrame(const Camera& camera, FrameBlock& block) {
    GlobePlacement placement(m_pyramid.manifest());
    placement.beginFrame(camera, block);
}

Result<bool> GlobeReferenceScene::addInstances(const Camera& camera, ReferenceBatch& batch,
                                               std::uint64_t maxRegions) {
    m_batch = &batch;
    m_camera = &camera;
    m_frustum = camera.frustum();
    m_gamma = camera.errorScale();
    m_cameraUp = globe::Wgs84::upAt(camera.position);
    m_maxRegions = maxRegions;
    m_visited = 0;
    m_complete = true;
    m_tiles.clear();
    Status status;
    for (int face = 0; face < globe::kCubeFaces && status && m_complete; ++face) {
        const globe::GlobePatchId root{face, 0, 0, 0};
        auto info = m_pyramid.patchInfo(io::layoutPatchOf(root));
        if (!info) {
            status = info.error();
            break;
        }
        if (info.value().present) {
            status = visitPatch(root, info.value());
        } else {
            // A face no source covers: the bare ellipsoid, drawn as such (layer −1).
            status = visitRegion({.id = root, .tileId = root, .bare = true});
        }
    }
    m_tiles.clear();
    m_batch = nullptr;
    if (!status) return status.error();
    return m_complete;
}

Status GlobeReferenceScene::visitPatch(const globe::GlobePatchId& id, const io::PatchInfo& info) {
    if (!withinLimit()) return {};
    const Region whole{
        .id = id, .tileId = id, .minHeight = info.minHeight, .maxHeight = info.maxHeight};
    if (info.presentChildren == 0) return visitRegion(whole);
    if (!frustumMeetsBox(m_frustum, globe::patchBounds(id, info.minHeight, info.maxHeight)))
        return {};
    const double half = 0.5 * double(m_layout.patchQuads());
    for (int c = 0; c < 4; ++c) {
        const globe::GlobePatchId child{id.face, id.level + 1, 2 * id.x + (c & 1),
                                        2 * id.y + (c >> 1)};
        if (((info.presentChildren >> c) & 1) != 0) {
            auto childInfo = m_pyramid.patchInfo(io::layoutPatchOf(child));
            if (!childInfo) return childInfo.error();
            if (!childInfo.value().present) {
                const io::PatchId layoutId = io::layoutPatchOf(child);
                return Error{
                    fmt::format("{}: patch (level {}, x {}, y {}) is absent, but its parent lists "
                                "it as present",
                                m_pyramid.shardFile(layoutId).string(), layoutId.level, layoutId.x,
                                layoutId.y)};
            }
            if (Status s = visitPatch(child, childInfo.value()); !s) return s;
            continue;
        }
        Region quadrant = whole;
        quadrant.id = child;
        quadrant.texelStep = 0.5;
        quadrant.texelOffsetX = double(c & 1) * half;
        quadrant.texelOffsetY = double(c >> 1) * half;
        if (Status s = visitRegion(quadrant); !s) return s;
    }
    return {};
}

bool GlobeReferenceScene::withinLimit() {
    if (++m_visited <= m_maxRegions) return true;
    m_complete = false;
    return false;
}

Status GlobeReferenceScene::visitRegion(const Region& region) {
    if (!withinLimit()) return {};
    const globe::OrientedBox box =
        globe::patchBounds(region.id, region.minHeight, region.maxHeight);
    if (!frustumMeetsBox(m_frustum, box)) return {};
    // How far the ellipsoid bulges over the region's flat cells, on screen (a metre's
    // distance at least: the camera may stand inside the box).
    const double spacing = globe::maxSampleSpacing(region.id.level, m_layout.patchQuads());
    const double rho = std::max(globe::distanceToBox(m_camera->position, box), 1.0);
    const double bulgePx = m_gamma * globe::flatTriangleErrorBound(spacing) / rho;
    if (bulgePx <= kCurvatureTolerancePx || region.id.level >= kMaxRegionLevel)
        return addRegion(region);
    const double half = 0.5 * double(m_layout.patchQuads()) * region.texelStep;
    for (int c = 0; c < 4; ++c) {
        Region part = region;
        part.id = {region.id.face, region.id.level + 1, 2 * region.id.x + (c & 1),
                   2 * region.id.y + (c >> 1)};
        part.texelStep = 0.5 * region.texelStep;
        part.texelOffsetX = region.texelOffsetX + double(c & 1) * half;
        part.texelOffsetY = region.texelOffsetY + double(c >> 1) * half;
        if (Status s = visitRegion(part); !s) return s;
    }
    return {};
}

Result<const io::PatchRecord*> GlobeReferenceScene::tileOf(const globe::GlobePatchId& id) {
    const io::PatchId layoutId = io::layoutPatchOf(id);
    const std::uint64_t key = tileKey(layoutId);
    if (auto found = m_tiles.find(key); found != m_tiles.end()) return &found->second;
    if (m_tiles.size() >= kKeptTiles) m_tiles.clear();
    auto read = m_pyramid.readPatch(layoutId);
    if (!read) return read.error();
    return &m_tiles.emplace(key, std::move(read).value()).first->second;
}

Status GlobeReferenceScene::addRegion(const Region& region) {
    PatchDraw draw;
    draw.id = io::layoutPatchOf(region.id);
    draw.minHeight = region.minHeight;
    draw.maxHeight = region.maxHeight;
    // The bare ellipsoid has no tile: layer −1 draws height 0. A tile is uploaded once a
    // batch, however many regions (quadrants, parts split for the curvature) draw from it.
    const auto layerOfTile = [&](const io::PatchId& layoutId) {
        return m_batch->layerOf(tileKey(layoutId), [&]() -> Result<std::span<const float>> {
            auto tile = tileOf(io::globePatchOf(layoutId));
            if (!tile) return tile.error();
            return std::span<const float>(tile.value()->heights);
        });
    };
    if (!region.bare) {
        auto layer = layerOfTile(io::layoutPatchOf(region.tileId));
        if (!layer) return layer.error();
        draw.layer = layer.value();
    }
    draw.tileId = io::layoutPatchOf(region.tileId);
    draw.isVirtual = region.texelStep != 1.0;
    draw.texelOffset = {static_cast<float>(region.texelOffsetX),
                        static_cast<float>(region.texelOffsetY)};
    draw.texelStep = static_cast<float>(region.texelStep);
    // The tiles above it for the footprint-filtered normals, as the LOD draw reads them
    // (ShadingTiles.h): every ancestor of a tile with data holds data, up to the face's root.
    std::array<ShadingTile, kShadingAncestors> shading;
    Status read;
    shadingTilesOf({.id = draw.tileId,
                    .texelOffset = draw.texelOffset,
                    .texelStep = draw.texelStep,
                    .layer = draw.layer},
                   m_layout.patchQuads(),
                   [&](AncestorTile& a) -> std::optional<int> {
                       if (a.id.level < io::ManifestGlobe::kLevelOffset || !read) return {};
                       auto layer = layerOfTile(a.id);
                       if (!layer) {
                           read = layer.error();
                           return {};
                       }
                       return layer.value();
                   },
                   shading);
    if (!read) return read;
    m_batch->add(globePatchInstance(draw, m_camera->position, m_cameraUp, m_layout.patchQuads()),
                 shading);
    return {};
}

}  // namespace terrain::runtime
