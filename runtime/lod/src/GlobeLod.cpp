#include "terrain/runtime/GlobeLod.h"

#include "terrain/base/Assert.h"
#include "terrain/pyramid/GlobeLayout.h"
#include "terrain/runtime/GlobeFrustum.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace terrain::runtime {
namespace {

std::uint64_t patchKey(const globe::GlobePatchId& id) {
    // face (3 bits) · level (5 bits) · x, y (28 bits each): every patch up to level 28.
    return (std::uint64_t(id.face) << 61) | (std::uint64_t(id.level) << 56) |
           (std::uint64_t(id.y) << 28) | std::uint64_t(id.x);
}

// A patch's share of GlobeLodStats::coverage (levels ≤ io::kMaxGlobeFaceLevel).
std::uint64_t coverageOf(int level) {
    return std::uint64_t{1} << (2 * (GlobeLodStats::kCoverageLevels - level));
}

}  // namespace

GlobeLod::GlobeLod(const io::PyramidManifest& manifest, TileResidency& residency,
                   const GlobeLodOptions& options)
    : m_residency(residency),
      m_options(options),
      m_quads(manifest.layout.patchQuads()),
      // The occluder lies inside the ground everywhere: below the deepest terrain.
      m_occluderShrink(std::max(0.0, -manifest.statistics.minHeight) + 1.0),
      m_occluder(m_occluderShrink) {
    TERRAIN_ASSERT(manifest.globe.has_value(), "GlobeLod needs a globe pyramid");
    TERRAIN_ASSERT(manifest.globe->faceFinestLevel <= io::kMaxGlobeFaceLevel,
                   "readManifest refuses deeper globe pyramids");
    TERRAIN_ASSERT(options.hysteresis >= 1.0, "GlobeLod: hysteresis below 1");
}

void GlobeLod::setOptions(const GlobeLodOptions& options) {
    TERRAIN_ASSERT(options.hysteresis >= 1.0, "GlobeLod: hysteresis below 1");
    m_options = options;
}

double GlobeLod::bareError(int level) const {
    return globe::flatTriangleErrorBound(globe::maxSampleSpacing(level, m_quads));
}

GlobeLod::PatchState& GlobeLod::stateOf(const globe::GlobePatchId& id, float minHeight,
                                        float maxHeight) {
    // A patch drawn bare until its tile arrives has other heights later: the state keeps the
    // heights its box was made for.
    auto [it, inserted] = m_patches.try_emplace(patchKey(id));
    PatchState& state = it->second;
    if (inserted || state.minHeight != minHeight || state.maxHeight != maxHeight) {
        state.box = globe::patchBounds(id, minHeight, maxHeight);
        state.minHeight = minHeight;
        state.maxHeight = maxHeight;
    }
    return state;
}

GlobePatchDraw GlobeLod::drawOf(const Node& node) const {
    GlobePatchDraw draw;
    draw.id = node.id;
    const double spacing = globe::maxSampleSpacing(node.id.level, m_quads);
    if (node.info == nullptr || node.isVirtual) {
        for (int d = 0; d < 4; ++d)
            draw.bareBlockErrorsM[static_cast<std::size_t>(d)] =
                static_cast<float>(globe::flatTriangleErrorBound(spacing * double(2 << d)));
    }
    if (node.info == nullptr) {
        draw.errorM = static_cast<float>(bareError(node.id.level));
        return draw;
    }
    draw.tileId = node.isVirtual ? node.tileId : node.id;
    draw.layer = m_residency.layerOf(io::layoutPatchOf(draw.tileId));
    draw.minHeight = node.info->minHeight;
    draw.maxHeight = node.info->maxHeight;
    draw.errorM = node.info->error;
    if (node.isVirtual) {
        draw.isVirtual = true;
        draw.errorM += static_cast<float>(bareError(node.id.level));
        draw.texelOffset = {static_cast<float>(node.texelOffsetX),
                            static_cast<float>(node.texelOffsetY)};
        draw.texelStep = static_cast<float>(node.texelStep);
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
    // A long flight: start again (one frame decided without hysteresis).
    if (m_patches.size() > 200000) m_patches.clear();
    ++m_frame;
    for (int face = 0; face < globe::kCubeFaces; ++face) {
        const globe::GlobePatchId root{face, 0, 0, 0};
        const io::PatchInfo* info =
            m_residency.acquire(io::layoutPatchOf(root), std::numeric_limits<float>::max());
        Node node;
        node.id = root;
        node.info = info;
        visit(node, stats, out);
    }
    return stats;
}

void GlobeLod::visit(const Node& node, GlobeLodStats& stats, std::vector<GlobePatchDraw>& out) {
    ++stats.visited;
    const bool data = node.info != nullptr && !node.isVirtual;
    const float minHeight = node.info != nullptr ? node.info->minHeight : 0.0f;
    const float maxHeight = node.info != nullptr ? node.info->maxHeight : 0.0f;
    // What a split can reduce: the whole Err(P) of a data patch with finer data under it;
    // elsewhere (no finer data, or none at all) the curvature alone.
    const double errorM = data && node.info->presentChildren != 0 ? double(node.info->error)
                                                                  : bareError(node.id.level);

    PatchState& state = stateOf(node.id, minHeight, maxHeight);
    const globe::OrientedBox& box = state.box;
    if (m_options.frustumCulling && !frustumMeetsBox(m_frustum, box)) {
        ++stats.frustumCulled;
        stats.coverage += coverageOf(node.id.level);
        return;
    }
    if (m_options.horizonCulling && m_occluder.isHidden(box)) {
        ++stats.horizonCulled;
        stats.coverage += coverageOf(node.id.level);
        return;
    }
    // A camera inside the box of a patch with finer data splits it (ρ = 0); the curvature
    // alone is never worth splitting for closer than a metre, or a camera standing on a
    // virtual patch would split it down to maxBareLevel.
    const bool finerData = data && node.info->presentChildren != 0;
    const double rho = finerData ? globe::distanceToBox(m_camera, box)
                                 : std::max(globe::distanceToBox(m_camera, box), 1.0);
    const double screenError =
        rho > 0.0 ? m_gamma * errorM / rho : std::numeric_limits<double>::infinity();
    // Split last frame (not culled nor merged since): held down to ε / hysteresis.
    const bool wasSplit = state.splitInFrame != 0 && state.splitInFrame + 1 == m_frame;
    const double threshold =
        wasSplit ? m_options.errorPx / m_options.hysteresis : m_options.errorPx;
    if (screenError > threshold &&
        node.id.level < std::min(m_options.maxBareLevel, io::kMaxGlobeFaceLevel)) {
        std::array<Node, 4> children;
        bool ready = true, failed = false;
        for (int c = 0; c < 4; ++c) {
            Node& child = children[static_cast<std::size_t>(c)];
            child.id = {node.id.face, node.id.level + 1, 2 * node.id.x + (c & 1),
                        2 * node.id.y + (c >> 1)};
            if (node.info == nullptr) continue;  // bare
            if (!data || ((node.info->presentChildren >> c) & 1) == 0) {
                // Virtual: this quadrant of the tile this patch draws.
                const double half = 0.5 * double(m_quads) * node.texelStep;
                child.info = node.info;
                child.isVirtual = true;
                child.tileId = node.isVirtual ? node.tileId : node.id;
                child.texelStep = 0.5 * node.texelStep;
                child.texelOffsetX = node.texelOffsetX + double(c & 1) * half;
                child.texelOffsetY = node.texelOffsetY + double(c >> 1) * half;
                continue;
            }
            const io::PatchId layoutId = io::layoutPatchOf(child.id);
            // A child that failed to load is never split into: this patch keeps drawing its
            // area (streaming counts the failure), as in the planar LOD, and nothing waits.
            if (m_residency.hasFailed(layoutId)) {
                failed = true;
                continue;
            }
            child.info = m_residency.acquire(layoutId, static_cast<float>(screenError));
            ready = ready && child.info != nullptr;
        }
        if (ready && !failed) {
            state.splitInFrame = m_frame;
            stats.heldSplits += screenError <= m_options.errorPx ? 1 : 0;
            for (const Node& child : children) visit(child, stats, out);
            return;
        }
        if (!failed) ++stats.waitingSplits;
    }
    out.push_back(drawOf(node));
    ++stats.drawn;
    stats.coverage += coverageOf(node.id.level);
    stats.drawnBare += node.info == nullptr ? 1 : 0;
    stats.drawnVirtual += node.isVirtual ? 1 : 0;
    stats.deepestLevel = std::max(stats.deepestLevel, node.id.level);
}

}  // namespace terrain::runtime
