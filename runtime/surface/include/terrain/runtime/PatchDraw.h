// PatchDraw: one patch of a frame as the LOD hands it to the draw, on either surface. A
// patch draws a tile of the GPU pool: its own (a data patch), an ancestor's quadrant (a
// virtual patch: the globe's pyramids are sparse, and a patch whose data ends draws its
// ancestor's tile interpolated), or none (a bare patch: the globe's ellipsoid where no data
// lies). On the plane every patch is a data patch.
#pragma once

#include "terrain/pyramid/PatchRecord.h"
#include "terrain/pyramid/PyramidLayout.h"

#include <array>
#include <cstdint>

namespace terrain::runtime {

struct PatchDraw {
    io::PatchId id;       ///< the layout patch (a globe patch: io::layoutPatchOf)
    int layer = -1;       ///< the GPU pool layer of its tile, or −1: bare (no tile)
    float errorM = 0.0f;  ///< Err(P), metres: Λ(d) = λ(d) + Err(P) (Yusov §5)
    /// How far below the edge the patch's skirts reach, metres (SkirtDepth.h).
    float skirtDepthM = 0.0f;
    float minHeight = 0.0f;  ///< of its tile (0 for a bare patch)
    float maxHeight = 0.0f;
    /// The tile it draws: `id` for a data patch, an ancestor for a virtual one, whose sample
    /// texelOffset + s · texelStep lies under the patch's sample s.
    io::PatchId tileId{};
    bool isVirtual = false;
    std::array<float, 2> texelOffset{0.0f, 0.0f};
    float texelStep = 1.0f;
    /// λ(1..4) of a patch without a tile of its own (bare or virtual): how far the surface
    /// bulges over its blocks simplified by 2^d (plus, for a virtual one, its tile's λ). For a
    /// patch with its own tile, what is added to the tile's λ: the sag and slope terms a native
    /// tile's λ leaves out (Surface::nativeGeometricErrors, blocksM); 0 for a face patch.
    std::array<float, 4> bareBlockErrorsM{};
    /// A native tile: the face patch (layout id) whose imagery it drapes, the finest of those
    /// that split into it (ImagerySelection; the imagery's tiles are the faces';
    /// NativeOwnership.h chooses it). Unused for any other.
    io::PatchId imageryPatch{};
    /// A native tile: where it owns the ground, the face patches it stands for (its native
    /// nodes' patches), as the cells of imageryPatch's level in an 8 × 8 window whose cell
    /// (0, 0) is imageryPatch's x, y plus nativeWindow: bit 8·j + i for cell (i, j). A tile
    /// reaches past them over face patches that drew themselves; there it draws nothing, so
    /// that the two surfaces do not fight for the same ground (docs/globe.md, "Native
    /// leaves"). 0: it owns all it covers (its patches lie on two faces, or beyond the window).
    std::uint64_t nativeCells = 0;
    std::array<std::int32_t, 2> nativeWindow{0, 0};
    /// How far its edges may part from a neighbour's beyond both their bounds, metres, for
    /// the skirts to reach (SkirtDepth.h): a native window's (runtime/lod NativeWindowTree)
    /// edges cross its source cells' diagonals between their vertices, where the sources'
    /// surface bends by the cell's twist; its drawn triangles lie between the two diagonals'
    /// surfaces, which its bound does not count. 0 for every other patch.
    float seamGapM = 0.0f;

    /// A data patch: `id` drawn from its own tile on `layer`, whose summary is `info`.
    static PatchDraw ofTile(const io::PatchId& id, int layer, const io::PatchInfo& info) {
        PatchDraw draw;
        draw.id = draw.tileId = id;
        draw.layer = layer;
        draw.errorM = info.error;
        draw.minHeight = info.minHeight;
        draw.maxHeight = info.maxHeight;
        return draw;
    }

    bool bare() const { return layer < 0; }
    /// A data patch: it draws its own tile.
    bool ownsTile() const { return layer >= 0 && !isVirtual; }
};

}  // namespace terrain::runtime
