// ImagerySelection: the frame's imagery tiles, a tree per layer shared by the drawn patches.
#include "terrain/runtime/ImagerySelection.h"

#include "terrain/pyramid/GlobeLayout.h"
#include "terrain/pyramid/NativeTiles.h"

#include "terrain/base/Assert.h"
#include "terrain/runtime/PlaneSurface.h"

#include <algorithm>
#include <cmath>
#include <tuple>

namespace terrain::runtime {
namespace {

/// The layout patch `levels` above `id` (x and y halved: on the globe's layout too).
io::PatchId ancestorOf(const io::PatchId& id, int levels) {
    return {id.level - levels, id.x >> levels, id.y >> levels};
}

/// Where patch `id`'s (u, v) lies on its ancestor `levels` above: offset + (u, v) · scale.
ImageryRoot placeInAncestor(const io::PatchId& id, int levels) {
    const double scale = std::ldexp(1.0, -levels);
    const std::int64_t mask = (std::int64_t{1} << levels) - 1;
    return {.offset = {static_cast<float>(static_cast<double>(id.x & mask) * scale),
                       static_cast<float>(static_cast<double>(id.y & mask) * scale)},
            .scale = static_cast<float>(scale),
            .node = -1};
}

}  // namespace

ImagerySelection::ImagerySelection(const Surface& surface, const io::PyramidManifest& manifest)
    : m_surface(surface), m_manifest(manifest) {
    for (const io::ManifestImageryLayer& layer : manifest.imagery) {
        if (static_cast<int>(m_layers.size()) == kMaxDrawnImageryLayers) break;
        m_layers.push_back({layer.coarsestLevel, layer.finestLevel, layer.opacity});
    }
}

std::vector<io::PatchId> ImagerySelection::coarsestTiles(int layer) const {
    const int level = m_layers[static_cast<std::size_t>(layer)].coarsestLevel;
    const io::PyramidLayout& layout = m_surface.layout();
    std::vector<io::PatchId> tiles;
    for (const io::PatchId& root : m_surface.roots()) {
        if (level < root.level) {
            tiles.push_back(ancestorOf(root, root.level - level));
            continue;
        }
        const int below = level - root.level;
        const std::int64_t side = std::int64_t{1} << below;
        for (std::int64_t y = 0; y < side; ++y) {
            for (std::int64_t x = 0; x < side; ++x) {
                const io::PatchId tile{level, (root.x << below) + x, (root.y << below) + y};
                // The plane's levels below its root cover the DEM, not the root's square.
                if (level <= layout.finestLevel() && !layout.contains(tile)) continue;
                tiles.push_back(tile);
            }
        }
    }
    std::sort(tiles.begin(), tiles.end(), [](const io::PatchId& a, const io::PatchId& b) {
        return std::tie(a.level, a.y, a.x) < std::tie(b.level, b.y, b.x);
    });
    tiles.erase(std::unique(tiles.begin(), tiles.end()), tiles.end());
    return tiles;
}

ImagerySelectionStats ImagerySelection::select(const Camera& camera,
                                               std::span<const PatchDraw> draws,
                                               ImageryResidency& imagery,
                                               const TileResidency& heights) {
    m_imagery = &imagery;
    m_heights = &heights;
    m_view = m_surface.view(camera);
    // Pixels per radian on the view axis: a texel of t metres at distance d spans t/d rad.
    m_pixelsPerRadian = camera.errorScale();
    m_stats = {};
    ++m_frame;
    m_volumesUsed = 0;
    m_roots.clear();
    m_nodes.clear();
    m_children.clear();
    m_nodeOf.clear();
    const int layers = layerCount();
    m_roots.reserve(draws.size() * static_cast<std::size_t>(layers));
    for (const PatchDraw& draw : draws) {
        if (io::isNativeTile(draw.id)) {
            addNativeRoots(draw);
            continue;
        }
        for (int l = 0; l < layers; ++l) {
            const Layer& layer = m_layers[static_cast<std::size_t>(l)];
            // A few levels above the patch, or above the layer's finest where the patch is
            // finer than the imagery: either way on the patch's line of ancestors.
            const int rootLevel =
                std::max(layer.coarsestLevel,
                         std::min(draw.id.level, layer.finestLevel) - kImageryRootLevelsAbove);
            const int above = draw.id.level - rootLevel;
            ImageryRoot root = placeInAncestor(draw.id, above);
            root.node = nodeOf(l, ancestorOf(draw.id, above));
            m_roots.push_back(root);
        }
    }
    m_stats.nodes = static_cast<int>(m_nodes.size());
    // The boxes of the view that moved on go once they outnumber this frame's.
    if (m_volumes.size() > 2 * m_volumesUsed + 1024)
        std::erase_if(m_volumes,
                      [&](const auto& entry) { return entry.second.lastFrame != m_frame; });
    m_imagery = nullptr;
    m_heights = nullptr;
    return m_stats;
}

void ImagerySelection::addNativeRoots(const PatchDraw& draw) {
    // A native tile drapes the imagery of the face patch it was split from: its vertices carry
    // their (u, v) on that patch (surface_globe.glsl, nativeImageryUv), and its root is the
    // patch's ancestor whose tile holds the native tile's whole outline (it reaches past the
    // patch), at least as far up as a face patch's root.
    const globe::NativeGridGeometry* grid = m_surface.nativeGeometry(draw.id);
    const std::optional<glm::dvec4> extent =
        grid != nullptr ? globe::nativeTileExtentOn(*grid, draw.id.x, draw.id.y,
                                                    io::globePatchOf(draw.imageryPatch))
                        : std::nullopt;
    const io::PatchId& patch = draw.imageryPatch;
    bool draped = false;
    for (int l = 0; l < layerCount(); ++l) {
        const Layer& layer = m_layers[static_cast<std::size_t>(l)];
        ImageryRoot root;
        const int first =
            patch.level - std::max(layer.coarsestLevel, std::min(patch.level, layer.finestLevel) -
                                                            kImageryRootLevelsAbove);
        for (int above = first; extent && patch.level - above >= layer.coarsestLevel; ++above) {
            // The ancestor's tile spans [−(x mod 2^above), that + 2^above) of the patch's u.
            const double side = std::ldexp(1.0, above);
            const std::int64_t mask = (std::int64_t{1} << above) - 1;
            const double u0 = -static_cast<double>(patch.x & mask);
            const double v0 = -static_cast<double>(patch.y & mask);
            if (extent->x >= u0 && extent->z <= u0 + side && extent->y >= v0 &&
                extent->w <= v0 + side) {
                root = placeInAncestor(patch, above);
                root.node = nodeOf(l, ancestorOf(patch, above));
                draped = true;
                break;
            }
        }
        m_roots.push_back(root);
    }
    // Across a cube edge no face tile holds it all: it draws no imagery (counted).
    if (!draped && layerCount() > 0) ++m_stats.nativeWithoutImagery;
}

int ImagerySelection::nodeOf(int layer, const io::PatchId& id) {
    const auto [found, isNew] = m_nodeOf.try_emplace(NodeKey{layer, id}, 0);
    if (!isNew) return found->second;
    const int index = static_cast<int>(m_nodes.size());
    found->second = index;
    m_nodes.push_back({});
    ImageryNode& node = m_nodes.back();
    node.level = id.level;
    if (const std::optional<int> gpu = m_imagery->gpuLayer(layer, id)) {
        node.gpuLayer = *gpu;
        ++m_stats.residentNodes;
    } else {
        // Not resident: drawn from the finest resident ancestor's texels until it arrives.
        // A root's ancestors are listed as nodes of their own only through this lookup.
        // Asked for unless it lies outside the view (a child of a tile the view cuts).
        // A tile read and found absent (a layer that does not reach here: a partial
        // layer's root under a patch far from its image) is not asked for again, nor
        // waited for: the ancestor's texels (transparent there) are all there is.
        const io::ImageryTileInfo* known = m_imagery->tileInfo(layer, id);
        const bool absent = known != nullptr && !known->present;
        if (const double pixels = absent ? 0.0 : texelPixels(id);
            pixels > 0.0 && !m_imagery->hasFailed(layer, id)) {
            m_imagery->want(layer, id, static_cast<float>(pixels));
            ++m_stats.wanted;
            ++m_stats.waiting;
        }
        const int coarsest = m_layers[static_cast<std::size_t>(layer)].coarsestLevel;
        for (int up = 1; id.level - up >= coarsest; ++up) {
            const io::PatchId ancestor = ancestorOf(id, up);
            if (const std::optional<int> held = m_imagery->gpuLayer(layer, ancestor)) {
                const ImageryRoot place = placeInAncestor(id, up);
                m_nodes[static_cast<std::size_t>(index)].gpuLayer = *held;
                m_nodes[static_cast<std::size_t>(index)].map = {place.offset[0], place.offset[1],
                                                                place.scale, 0.0f};
                break;
            }
        }
        return index;  // its children are unknown until it is read
    }
    expand(layer, index, id);
    return index;
}

void ImagerySelection::expand(int layer, int index, const io::PatchId& id) {
    if (id.level >= m_layers[static_cast<std::size_t>(layer)].finestLevel) return;
    const io::ImageryTileInfo* info = m_imagery->tileInfo(layer, id);
    if (info == nullptr || info->presentChildren == 0) return;
    if (texelPixels(id) <= 1.0) return;
    const int entry = static_cast<int>(m_children.size());
    m_children.push_back({-1, -1, -1, -1});
    m_nodes[static_cast<std::size_t>(index)].children = entry;
    const ImageryNode parent = m_nodes[static_cast<std::size_t>(index)];
    for (int q = 0; q < 4; ++q) {
        const io::PatchId child{id.level + 1, 2 * id.x + (q & 1), 2 * id.y + (q >> 1)};
        int childIndex;
        if ((info->presentChildren & (1u << q)) != 0) {
            childIndex = nodeOf(layer, child);
        } else {
            // No finer imagery here: the child draws its parent's quadrant (transparent where
            // the parent is).
            childIndex = static_cast<int>(m_nodes.size());
            ImageryNode inherited = parent;
            inherited.children = -1;
            inherited.level = child.level;
            inherited.map = {parent.map[0] + parent.map[2] * 0.5f * static_cast<float>(q & 1),
                             parent.map[1] + parent.map[2] * 0.5f * static_cast<float>(q >> 1),
                             parent.map[2] * 0.5f, 0.0f};
            m_nodes.push_back(inherited);
        }
        m_children[static_cast<std::size_t>(entry)][static_cast<std::size_t>(q)] = childIndex;
    }
}

double ImagerySelection::texelMetres(int level) const {
    if (m_surface.kind() == SurfaceKind::Plane) {
        const TerrainGeometry& geometry = planeGeometry(m_surface);
        const int finest = geometry.layout().finestLevel();
        const glm::dvec2 size = geometry.patchSize(std::min(level, finest));
        return std::ldexp(std::max(size.x, size.y), std::min(0, finest - level)) /
               io::kImageryInteriorTexels;
    }
    const int deepest = m_surface.maxLevel();
    return std::ldexp(m_surface.sampleSpacingM(std::min(level, deepest)),
                      std::min(0, deepest - level)) *
           m_surface.layout().patchQuads() / io::kImageryInteriorTexels;
}

PatchVolume ImagerySelection::volumeOf(const io::PatchId& id) {
    // Heights from the finest resident patch at or above the tile (the LOD keeps the drawn
    // patches' ancestors resident); none (the globe's bare ellipsoid): 0.
    const int deepest = m_surface.maxLevel();
    const io::PatchId clamped = ancestorOf(id, std::max(0, id.level - deepest));
    float minHeight = 0.0f, maxHeight = 0.0f;
    const int rootLevel = m_surface.roots().front().level;
    for (int up = 0; clamped.level - up >= rootLevel; ++up) {
        if (const io::PatchInfo* info = m_heights->residentInfo(ancestorOf(clamped, up))) {
            minHeight = info->minHeight;
            maxHeight = info->maxHeight;
            break;
        }
    }
    if (m_surface.kind() == SurfaceKind::Plane && id.level > deepest) {
        // Past the DEM's finest level: the finest patch's box cut to the tile's footprint.
        const TerrainGeometry& geometry = planeGeometry(m_surface);
        Aabb box = std::get<Aabb>(surfaceVolume(clamped, minHeight, maxHeight));
        const io::PlanarSamplePoint a = io::planarImageryPoint(geometry.layout(), id, 0.0, 0.0);
        const io::PlanarSamplePoint b = io::planarImageryPoint(geometry.layout(), id, 1.0, 1.0);
        const glm::dvec2 wa = geometry.worldOfSample(a.column, a.row);
        const glm::dvec2 wb = geometry.worldOfSample(b.column, b.row);
        box.min.x = std::min(wa.x, wb.x);
        box.max.x = std::max(wa.x, wb.x);
        box.min.y = std::min(wa.y, wb.y);
        box.max.y = std::max(wa.y, wb.y);
        return box;
    }
    // On the globe a tile past the deepest level the surface splits to takes that level's
    // volume (nearer than its own: it may be listed a level early, never late).
    return surfaceVolume(clamped, minHeight, maxHeight);
}

const PatchVolume& ImagerySelection::surfaceVolume(const io::PatchId& id, float minHeight,
                                                   float maxHeight) {
    const auto [found, isNew] = m_volumes.try_emplace(id);
    CachedVolume& cached = found->second;
    if (isNew || cached.minHeight != minHeight || cached.maxHeight != maxHeight) {
        cached.minHeight = minHeight;
        cached.maxHeight = maxHeight;
        cached.volume = m_surface.volume(id, minHeight, maxHeight);
    }
    if (cached.lastFrame != m_frame) {
        cached.lastFrame = m_frame;
        ++m_volumesUsed;
    }
    return cached.volume;
}

double ImagerySelection::texelPixels(const io::PatchId& id) {
    const PatchVolume volume = volumeOf(id);
    int planes = 0b11111;
    if (m_surface.outsideFrustum(m_view, volume, planes)) return 0.0;
    const double distance = std::max(m_surface.distance(m_view.camera, volume), 1.0e-3);
    return texelMetres(id.level) * m_pixelsPerRadian / distance;
}

}  // namespace terrain::runtime
