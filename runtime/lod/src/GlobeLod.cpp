#include "terrain/runtime/GlobeLod.h"

#include "terrain/base/Assert.h"
#include "terrain/io/GlobeLayout.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace terrain::runtime {
namespace {

std::uint64_t boundsKey(const globe::GlobePatchId& id) {
    // face (3 bits) · level (5 bits) · x, y (28 bits each): every patch up to level 28.
    return (std::uint64_t(id.face) << 61) | (std::uint64_t(id.level) << 56) |
           (std::uint64_t(id.y) << 28) | std::uint64_t(id.x);
}

bool outsideFrustum(const Frustum& frustum, const globe::OrientedBox& box) {
    for (const glm::dvec4& plane : frustum.planes) {
        const glm::dvec3 n(plane);
        double reach = 0.0;
        for (int axis = 0; axis < 3; ++axis)
            reach += std::abs(glm::dot(n, box.axes[axis])) * box.halfExtents[axis];
        if (glm::dot(n, box.centre) + plane.w + reach < 0.0) return true;
    }
    return false;
}

}  // namespace

GlobeLod::GlobeLod(const io::PyramidManifest& manifest, TileResidency& residency,
                   const GlobeLodOptions& options)
    : m_residency(residency),
      m_options(options),
      m_quads(manifest.layout.patchQuads()),
      m_finestDataLevel(manifest.globe ? manifest.globe->faceFinestLevel : 0),
      // The occluder lies inside the ground everywhere: below the deepest terrain.
      m_occluderShrink(std::max(0.0, -manifest.statistics.minHeight) + 1.0),
      m_occluder(m_occluderShrink) {
    TERRAIN_ASSERT(manifest.globe.has_value(), "GlobeLod needs a globe pyramid");
}

double GlobeLod::bareError(int level) const {
    return globe::flatTriangleErrorBound(globe::maxSampleSpacing(level, m_quads));
}

const globe::OrientedBox& GlobeLod::boundsOf(const globe::GlobePatchId& id, float minHeight,
                                             float maxHeight) {
    // A patch drawn bare until its tile arrives has other heights later: the cache keeps the
    // heights its box was made for.
    auto [it, inserted] = m_bounds.try_emplace(boundsKey(id));
    CachedBounds& cached = it->second;
    if (inserted || cached.minHeight != minHeight || cached.maxHeight != maxHeight)
        cached = {globe::patchBounds(id, minHeight, maxHeight), minHeight, maxHeight};
    return cached.box;
}

GlobePatchDraw GlobeLod::drawOf(const Node& node) const {
    GlobePatchDraw draw;
    draw.id = node.id;
    if (node.info != nullptr) {
        draw.layer = m_residency.layerOf(io::layoutPatchOf(node.id));
        draw.errorM = node.info->error;
        draw.minHeight = node.info->minHeight;
        draw.maxHeight = node.info->maxHeight;
    } else {
        draw.errorM = static_cast<float>(bareError(node.id.level));
        const double spacing = globe::maxSampleSpacing(node.id.level, m_quads);
        for (int d = 0; d < 4; ++d)
            draw.bareBlockErrorsM[static_cast<std::size_t>(d)] =
                static_cast<float>(globe::flatTriangleErrorBound(spacing * double(2 << d)));
    }
    return draw;
}

GlobeLodStats GlobeLod::select(const Camera& camera, std::vector<GlobePatchDraw>& out) {
    out.clear();
    GlobeLodStats stats;
    m_camera = camera.position;
    m_gamma = camera.errorScale();
    m_frustum = camera.frustum();
    m_occluder.setCamera(camera.position);
    if (m_bounds.size() > 200000) m_bounds.clear();  // a long flight: start the cache again
    for (int face = 0; face < globe::kCubeFaces; ++face) {
        const globe::GlobePatchId root{face, 0, 0, 0};
        const io::PatchInfo* info =
            m_residency.acquire(io::layoutPatchOf(root), std::numeric_limits<float>::max());
        visit({root, info}, stats, out);
    }
    return stats;
}

void GlobeLod::visit(const Node& node, GlobeLodStats& stats, std::vector<GlobePatchDraw>& out) {
    ++stats.visited;
    const bool data = node.info != nullptr;
    const float minHeight = data ? node.info->minHeight : 0.0f;
    const float maxHeight = data ? node.info->maxHeight : 0.0f;
    const double errorM = data ? double(node.info->error) : bareError(node.id.level);
    const globe::OrientedBox& box = boundsOf(node.id, minHeight, maxHeight);
    if (m_options.frustumCulling && outsideFrustum(m_frustum, box)) {
        ++stats.frustumCulled;
        return;
    }
    if (m_options.horizonCulling && m_occluder.isHidden(box)) {
        ++stats.horizonCulled;
        return;
    }
    const double rho = globe::distanceToBox(m_camera, box);
    const double screenError =
        rho > 0.0 ? m_gamma * errorM / rho : std::numeric_limits<double>::infinity();
    const int finest = data ? m_finestDataLevel : m_options.maxBareLevel;
    if (screenError > m_options.errorPx && node.id.level < finest) {
        std::array<Node, 4> children;
        bool ready = true;
        for (int c = 0; c < 4; ++c) {
            Node& child = children[static_cast<std::size_t>(c)];
            child.id = {node.id.face, node.id.level + 1, 2 * node.id.x + (c & 1),
                        2 * node.id.y + (c >> 1)};
            if (!data || ((node.info->presentChildren >> c) & 1) == 0) continue;  // bare
            const io::PatchId layoutId = io::layoutPatchOf(child.id);
            // A child that failed to load is never split into: this patch keeps drawing its
            // area (streaming counts the failure), as in the planar LOD.
            child.info = m_residency.hasFailed(layoutId)
                             ? nullptr
                             : m_residency.acquire(layoutId, static_cast<float>(screenError));
            ready = ready && child.info != nullptr;
        }
        if (ready) {
            for (const Node& child : children) visit(child, stats, out);
            return;
        }
        ++stats.waitingSplits;
    }
    out.push_back(drawOf(node));
    ++stats.drawn;
    stats.drawnBare += data ? 0 : 1;
    stats.deepestLevel = std::max(stats.deepestLevel, node.id.level);
}

}  // namespace terrain::runtime
