// ShadingTiles: the tiles above a drawn patch's own, from which its footprint-filtered normals
// are taken (shaders/terrain_footprint.glsl; issue 46, "a pixel's normal must not depend on
// which level's patch draws it"). Where a pixel spans several of a patch's samples its normal
// is the mean slope over its footprint. Taken from the patch's own tile, the box is cut at
// the tile's edge, so the pixels along a patch boundary get the slope of part of their
// footprint, different on either side: bright or dark pixels along the boundaries of distant
// patches. Taken from the level whose samples are about a footprint apart (the k-th tile
// above, as a mip chain's level), the box spans at most two of its samples and stays inside
// its apron, and the level depends on the footprint in metres only: both sides of a boundary,
// whatever their levels, and the reference's finest tiles read the same data.
//
// The LOD quadtree keeps every ancestor of a drawn patch resident (it pins the nodes it
// holds), so the tiles are in the GPU pool already; the reference renderers upload theirs.
#pragma once

#include "Bindings.h"
#include "terrain/pyramid/PyramidLayout.h"

#include <array>
#include <functional>
#include <optional>
#include <span>

namespace terrain::runtime {

/// Tiles above its own that each drawn patch lists.
inline constexpr int kShadingAncestors = TERRAIN_SHADING_ANCESTORS;

/// One of them as the shaders read it: its sample x + s · z lies under the patch's sample s
/// (the patch's texelMap, for that tile), w its layer (−1: none, the bare surface).
using ShadingTile = std::array<float, 4>;

/// The tile a patch draws and where: its sample texelOffset + s · texelStep lies under the
/// patch's sample s (PatchDraw's fields), on `layer` (−1: bare).
struct DrawnTile {
    io::PatchId id;
    std::array<float, 2> texelOffset{0.0f, 0.0f};
    float texelStep = 1.0f;
    int layer = -1;
};

/// Where the tile k levels above `tile.id` is (its layout parent k times: level − k, x and y
/// halved k times, on the globe's layout too), and the patch's samples on it.
struct AncestorTile {
    io::PatchId id;
    std::array<float, 2> texelOffset{0.0f, 0.0f};
    float texelStep = 1.0f;
};
AncestorTile ancestorTile(const DrawnTile& tile, int k, int patchQuads);

/// Fills `out` with the tiles 1 … kShadingAncestors levels above `tile` (out[k − 1]), each
/// on the layer `layerOf(ancestor)` gives; it may move the ancestor's texelOffset to where it
/// put the tile's samples (a window cut from it). Where it gives nullopt (not resident, above
/// the root), that entry and those above it repeat the coarsest tile found (the shader's box
/// is then cut at its edge); a bare tile (layer −1) lists bare tiles, and a native tile
/// (io::isNativeTile, a level of its source's own grid) itself.
void shadingTilesOf(const DrawnTile& tile, int patchQuads,
                    const std::function<std::optional<int>(AncestorTile&)>& layerOf,
                    std::span<ShadingTile, kShadingAncestors> out);

}  // namespace terrain::runtime
