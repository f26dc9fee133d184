// ImagerySelection: which imagery tiles a frame draws, chosen per pixel footprint and
// independently of the geometry's patch levels (issue 47, "each pixel takes imagery from the
// level whose texels match its footprint").
//
// For every drawn patch and imagery layer the frame lists a root tile a few levels above
// the patch (so pixels that see the patch small still find texels as large as they are),
// and under it a tree of tiles: a tile's children are listed where its texels would cover
// more than a pixel at the nearest point of its volume inside the frustum, and the layer has
// them. A listed tile that is not resident yet is drawn from its finest resident ancestor
// (its texels mapped from there: never a hole) and is asked for, at a priority of its
// texels' size in pixels. The fragment stage (shaders/terrain_imagery.glsl) walks the tree
// from its patch's root down to the level its own footprint wants and samples that tile's
// mips, so the level follows the pixel, not the patch, and two patches of different levels
// meet on the same texels.
//
// A native tile (docs/globe.md, "Native leaves") drapes the face patch it was split from:
// its vertices carry their (u, v) on that patch, and its root is the ancestor whose tile holds
// its whole outline.
//
// Nodes are shared by id across the patches of a frame: the tree is the frame's, not a
// patch's. Pure CPU (no GL); the draw uploads what it lists (TerrainRenderer).
#pragma once

#include "terrain/pyramid/PatchIdHash.h"
#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/ImageryResidency.h"
#include "terrain/runtime/PatchDraw.h"
#include "terrain/runtime/Surface.h"
#include "terrain/runtime/TileResidency.h"

#include <array>
#include <cstdint>
#include <span>
#include <unordered_map>
#include <vector>

namespace terrain::runtime {

/// Imagery layers one draw composites (more are refused when a session opens); the shaders'
/// TERRAIN_MAX_IMAGERY_LAYERS (the draw asserts they agree).
inline constexpr int kMaxDrawnImageryLayers = 4;
/// Levels a patch's root tile lies above the patch (or above the layer's finest level):
/// with the tiles' own kImageryTileMips mips, pixels up to 2^(3 + 2) interior texels of the
/// patch's own level wide find a tile whose texels match them.
inline constexpr int kImageryRootLevelsAbove = 3;

/// One listed tile as the shaders read it (std430, 32 bytes): the texture-array layer it is
/// drawn from (−1: nothing, the layer is transparent here), its children's entry in the
/// children list (−1: not listed), and where its patch-local (u, v) lies on that layer's
/// tile: tileUv = map.xy + (u, v) · map.z (its own tile: (0, 0, 1); an ancestor's: the
/// quadrant it is of that tile).
struct ImageryNode {
    std::int32_t gpuLayer = -1;
    std::int32_t children = -1;
    std::int32_t level = 0;
    std::int32_t unused = 0;
    std::array<float, 4> map{0.0f, 0.0f, 1.0f, 0.0f};
};
static_assert(sizeof(ImageryNode) == 32);

/// A drawn patch's root for one layer (std430, 16 bytes): the patch's (u, v) lies at
/// offset + (u, v) · scale of the root tile's; node −1: the layer draws nothing on it.
struct ImageryRoot {
    std::array<float, 2> offset{0.0f, 0.0f};
    float scale = 1.0f;
    std::int32_t node = -1;
};
static_assert(sizeof(ImageryRoot) == 16);

struct ImagerySelectionStats {
    int nodes = 0;          ///< tiles listed, all layers
    int residentNodes = 0;  ///< of them drawn from their own tile
    int wanted = 0;         ///< want() calls (tiles not resident)
    /// Listed tiles not resident that have not failed: the view is not settled until none
    /// is left.
    int waiting = 0;
    /// Native tiles drawn without imagery: no face tile holds their whole outline (they
    /// cross a cube edge, or the layer's coarsest level is finer than that).
    int nativeWithoutImagery = 0;
};

class ImagerySelection {
public:
    /// The first kMaxDrawnImageryLayers layers of `manifest` (terrain-imagery adds no more).
    ImagerySelection(const Surface& surface, const io::PyramidManifest& manifest);

    int layerCount() const { return static_cast<int>(m_layers.size()); }
    /// The manifest's opacity of layer `layer`.
    double layerOpacity(int layer) const {
        return m_layers[static_cast<std::size_t>(layer)].opacity;
    }

    /// Lists this frame's tiles for `draws` seen from `camera`: roots per (patch, layer),
    /// nodes and children, asking `imagery` for the tiles wanted. `heights` gives the volumes'
    /// height ranges (the finest resident patch at or above a tile). Allocates only until
    /// its lists reach their high-water marks.
    ImagerySelectionStats select(const Camera& camera, std::span<const PatchDraw> draws,
                                 ImageryResidency& imagery, const TileResidency& heights);

    /// Layer `layer`'s coarsest tiles: those of its coarsest level under the surface's roots
    /// (the plane's root patch, the globe's six cube faces). Every frame's tree starts at or
    /// below them, so with them resident no drawn pixel lacks imagery.
    std::vector<io::PatchId> coarsestTiles(int layer) const;

    /// layerCount() roots per drawn patch, patch-major.
    std::span<const ImageryRoot> roots() const { return m_roots; }
    std::span<const ImageryNode> nodes() const { return m_nodes; }
    /// Four node indices per entry (quadrant cy · 2 + cx).
    std::span<const std::array<std::int32_t, 4>> children() const { return m_children; }

private:
    struct Layer {
        int coarsestLevel = 0;
        int finestLevel = 0;
        double opacity = 1.0;
    };
    struct NodeKey {
        int layer = 0;
        io::PatchId id;
        bool operator==(const NodeKey&) const = default;
    };
    struct NodeKeyHash {
        std::size_t operator()(const NodeKey& k) const {
            return io::PatchIdHash{}(k.id) * 31u + static_cast<std::size_t>(k.layer);
        }
    };

    /// The node of tile `id` of `layer`, listing it (and what it inherits) when new.
    int nodeOf(int layer, const io::PatchId& id);
    /// A native tile's roots, one per layer (addNativeRoots in the .cpp says how).
    void addNativeRoots(const PatchDraw& draw);
    /// Lists the children of node `index` where its texels are larger than a pixel.
    void expand(int layer, int index, const io::PatchId& id);
    /// Interior texels' size on screen, pixels, at the nearest point of the tile's volume;
    /// 0 when the volume lies outside the frustum.
    double texelPixels(const io::PatchId& id);
    PatchVolume volumeOf(const io::PatchId& id);
    /// m_surface.volume(id, minHeight, maxHeight), kept from the frames that computed it: a
    /// globe patch's box costs thousands of points, and the same boxes serve every frame
    /// (and every tile past the surface's deepest level) until their heights change.
    const PatchVolume& surfaceVolume(const io::PatchId& id, float minHeight, float maxHeight);
    double texelMetres(int level) const;

    const Surface& m_surface;
    const io::PyramidManifest& m_manifest;
    std::vector<Layer> m_layers;
    // The frame's inputs while select() runs.
    ImageryResidency* m_imagery = nullptr;
    const TileResidency* m_heights = nullptr;
    SurfaceView m_view;
    double m_pixelsPerRadian = 1.0;
    ImagerySelectionStats m_stats;

    std::vector<ImageryRoot> m_roots;
    std::vector<ImageryNode> m_nodes;
    std::vector<std::array<std::int32_t, 4>> m_children;
    std::unordered_map<NodeKey, int, NodeKeyHash> m_nodeOf;

    struct CachedVolume {
        float minHeight = 0.0f;
        float maxHeight = 0.0f;
        PatchVolume volume;
        std::uint64_t lastFrame = 0;  ///< the select() that last used it
    };
    std::unordered_map<io::PatchId, CachedVolume, io::PatchIdHash> m_volumes;
    std::uint64_t m_frame = 0;      ///< select() calls so far
    std::size_t m_volumesUsed = 0;  ///< of m_volumes, used by this select()
};

}  // namespace terrain::runtime
