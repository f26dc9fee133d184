// GlobeReferenceRenderer: the pyramid walked on disk down to the finest data, regions split for
// the ellipsoid's curvature only, uploaded a batch at a time into a texture array and drawn as
// instances of one grid of indexed triangles.
#include "terrain/runtime/GlobeReferenceRenderer.h"

#include "terrain/base/Assert.h"
#include "terrain/gl/ReversedZScope.h"
#include "terrain/globe/PatchBounds.h"
#include "terrain/globe/Wgs84.h"
#include "terrain/pyramid/GlobeLayout.h"
#include "terrain/runtime/GlobeFrustum.h"
#include "terrain/runtime/ProgramBuilder.h"
#include "terrain/runtime/SurfacePlacement.h"

#include <epoxy/gl.h>
#include <fmt/format.h>
#include <glm/gtc/type_ptr.hpp>

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

Result<GlobeReferenceRenderer> GlobeReferenceRenderer::create(const io::PyramidManifest& manifest) {
    TERRAIN_ASSERT(manifest.globe.has_value(), "GlobeReferenceRenderer draws globe pyramids");
    ProgramBuilder builder("globe reference");
    builder.stage("globe_reference.vert").stage("reference.frag");
    auto program = builder.build();
    if (!program) return program.error();

    GlobeReferenceRenderer r;
    r.m_program = std::move(program).value();
    r.m_layout = manifest.layout;
    r.m_heightRange = globeHeightRange(manifest);
    r.m_grid = SampleGrid::create(manifest.layout.patchQuads(), "globe reference grid");
    r.m_instances = gl::Buffer::create(sizeof(PatchInstance) * kBatchRegions,
                                       GL_DYNAMIC_STORAGE_BIT, "globe reference regions");
    const int side = manifest.layout.tileSamples();
    auto heights = gl::Texture::create2DArray(
        {.internalFormat = GL_R32F, .width = side, .height = side, .layers = kBatchRegions},
        "globe reference tiles");
    if (!heights) return heights.error();
    r.m_heights = std::move(heights).value();
    r.m_heights.setSampling(GL_NEAREST, GL_NEAREST, GL_CLAMP_TO_EDGE);
    r.m_staging.reserve(kBatchRegions);
    r.m_layerTiles.reserve(kBatchRegions);
    return r;
}

Result<ReferenceDrawStats> GlobeReferenceRenderer::draw(const Camera& camera,
                                                        io::PyramidReader& pyramid,
                                                        const ReferenceStyle& style,
                                                        std::uint64_t maxRegions) {
    TERRAIN_ASSERT(pyramid.layout().patchQuads() == m_layout.patchQuads(),
                   "GlobeReferenceRenderer: created for another patch size");
    m_pyramid = &pyramid;
    m_camera = &camera;
    m_frustum = camera.frustum();
    m_gamma = camera.errorScale();
    m_cameraUp = globe::Wgs84::upAt(camera.position);
    m_stats = {};
    m_maxRegions = maxRegions;
    m_visited = 0;
    m_staging.clear();
    m_layerTiles.clear();
    m_tiles.clear();

    // Placed and shaded as the globe draw, so both draws are equally exact and alike.
    const glm::mat4 viewProjection(camera.relativeViewProjection());
    m_program.setUniformMat4("u_viewProjection",
                             std::span<const float, 16>(glm::value_ptr(viewProjection), 16));
    m_program.setUniform("u_patchQuads", m_layout.patchQuads());
    const glm::vec3 sun(globeSunDirection(camera));
    m_program.setUniform("u_sunDirection", std::array<float, 3>{sun.x, sun.y, sun.z});
    m_program.setUniform("u_heightRangeM", m_heightRange);
    m_program.setUniform("u_skyColor", style.skyColor);
    m_program.setUniform("u_fogDensityPerM", style.fogDensityPerM);
    m_program.setUniform("u_demFirstSample", std::array<float, 2>{-1e30f, -1e30f});
    m_program.setUniform("u_demLastSample", std::array<float, 2>{1e30f, 1e30f});

    const gl::ReversedZScope reversedZ;
    Status status;
    for (int face = 0; face < globe::kCubeFaces && status && m_stats.complete; ++face) {
        const globe::GlobePatchId root{face, 0, 0, 0};
        auto info = pyramid.patchInfo(io::layoutPatchOf(root));
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
    if (status && !m_staging.empty()) submitBatch();
    m_staging.clear();
    m_layerTiles.clear();
    m_tiles.clear();
    if (!status) return status.error();
    m_stats.triangles = m_stats.tiles * 2 * static_cast<std::uint64_t>(m_layout.patchQuads()) *
                        static_cast<std::uint64_t>(m_layout.patchQuads());
    return m_stats;
}

Status GlobeReferenceRenderer::visitPatch(const globe::GlobePatchId& id,
                                          const io::PatchInfo& info) {
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
            auto childInfo = m_pyramid->patchInfo(io::layoutPatchOf(child));
            if (!childInfo) return childInfo.error();
            if (!childInfo.value().present) {
                const io::PatchId layoutId = io::layoutPatchOf(child);
                return Error{
                    fmt::format("{}: patch (level {}, x {}, y {}) is absent, but its parent lists "
                                "it as present",
                                m_pyramid->shardFile(layoutId).string(), layoutId.level, layoutId.x,
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

bool GlobeReferenceRenderer::withinLimit() {
    if (++m_visited <= m_maxRegions) return true;
    m_stats.complete = false;
    return false;
}

Status GlobeReferenceRenderer::visitRegion(const Region& region) {
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

Result<const io::PatchRecord*> GlobeReferenceRenderer::tileOf(const globe::GlobePatchId& id) {
    const io::PatchId layoutId = io::layoutPatchOf(id);
    const std::uint64_t key = tileKey(layoutId);
    if (auto found = m_tiles.find(key); found != m_tiles.end()) return &found->second;
    if (m_tiles.size() >= kKeptTiles) m_tiles.clear();
    auto read = m_pyramid->readPatch(layoutId);
    if (!read) return read.error();
    return &m_tiles.emplace(key, std::move(read).value()).first->second;
}

Status GlobeReferenceRenderer::addRegion(const Region& region) {
    PatchDraw draw;
    draw.id = io::layoutPatchOf(region.id);
    draw.minHeight = region.minHeight;
    draw.maxHeight = region.maxHeight;
    // The bare ellipsoid has no tile: layer −1 draws height 0. A tile is uploaded once a
    // batch, however many regions (quadrants, parts split for the curvature) draw from it.
    if (!region.bare) {
        const std::uint64_t key = tileKey(io::layoutPatchOf(region.tileId));
        const auto uploaded = std::find(m_layerTiles.begin(), m_layerTiles.end(), key);
        draw.layer = static_cast<int>(uploaded - m_layerTiles.begin());
        if (uploaded == m_layerTiles.end()) {
            auto tile = tileOf(region.tileId);
            if (!tile) return tile.error();
            const int side = m_layout.tileSamples();
            m_heights.upload({.x = 0, .y = 0, .layer = draw.layer, .width = side, .height = side},
                             GL_RED, GL_FLOAT, std::as_bytes(std::span(tile.value()->heights)));
            m_layerTiles.push_back(key);
        }
    }
    draw.tileId = io::layoutPatchOf(region.tileId);
    draw.isVirtual = region.texelStep != 1.0;
    draw.texelOffset = {static_cast<float>(region.texelOffsetX),
                        static_cast<float>(region.texelOffsetY)};
    draw.texelStep = static_cast<float>(region.texelStep);
    m_staging.push_back(
        globePatchInstance(draw, m_camera->position, m_cameraUp, m_layout.patchQuads()));
    ++m_stats.tiles;
    // A batch holds at most as many tiles as regions: full regions, full layers.
    if (static_cast<int>(m_staging.size()) == kBatchRegions) submitBatch();
    return {};
}

void GlobeReferenceRenderer::submitBatch() {
    m_instances.upload(0, std::as_bytes(std::span(m_staging)));
    m_grid.draw(m_program, m_heights, m_instances, static_cast<int>(m_staging.size()));
    ++m_stats.batches;
    m_staging.clear();
    m_layerTiles.clear();
}

}  // namespace terrain::runtime
