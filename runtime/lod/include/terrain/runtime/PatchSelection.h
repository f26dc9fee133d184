// PatchSelection: the coarse LOD of Yusov & Shevtsov 2011, §5, selected from the root
// every frame: a patch is split when its screen-space error
//     Err_Scr(P) = γ · Err(P) / ρ(c, V)
// exceeds the threshold ε and all four children are resident on the GPU; otherwise it is
// drawn and its missing children are requested, highest screen-space error first. So every
// drawn patch is resident, and a patch whose children are late or failed keeps being drawn
// in their place: the terrain never has a hole.
//
// This is the stateless selector the streaming stress tool drives and the reference a
// frame-coherent quadtree is measured against; it visits every patch it keeps or splits.
#pragma once

#include "terrain/pyramid/PyramidLayout.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/TerrainGeometry.h"
#include "terrain/runtime/TileResidency.h"

#include <cstdint>
#include <vector>

namespace terrain::runtime {

struct PatchDraw {
    io::PatchId id;
    int layer = -1;       ///< the patch's layer in the GPU tile pool's texture arrays
    float errorM = 0.0f;  ///< Err(P), metres: Λ(d) = λ(d) + Err(P) (Yusov §5)
    /// How far below the edge the patch's skirts reach, metres (see the renderer).
    float skirtDepthM = 0.0f;
};

struct PatchSelectionStats {
    std::uint64_t drawn = 0;
    std::uint64_t culled = 0;         ///< resident patches outside the frustum (not drawn)
    std::uint64_t visited = 0;        ///< patches whose screen-space error was evaluated
    std::uint64_t waitingSplits = 0;  ///< drawn although too coarse: children not resident
    /// Finest-level patches under the drawn and culled patches; equals
    /// finestPatchesCovered(root) when they tile the domain (and something was drawn).
    std::uint64_t coveredFinestPatches = 0;
};

/// Selects the patches to draw for `camera` at threshold `errorPx` (ε, pixels), asking
/// `residency` for every patch it needs. `out` is cleared and filled; it keeps its
/// capacity, so steady frames do not allocate. Empty until the root is resident.
PatchSelectionStats selectPatches(const Camera& camera, const TerrainGeometry& geometry,
                                  double errorPx, TileResidency& residency,
                                  std::vector<PatchDraw>& out);

/// The children of `id` inside the layout (1 to 4; fewer at the right and bottom edges).
int containedChildren(const io::PyramidLayout& layout, const io::PatchId& id,
                      io::PatchId (&children)[4]);

/// Finest-level patches under `id` (clipped to the layout): the patch's share of the
/// domain, for checking that selected patches tile it exactly once.
std::uint64_t finestPatchesCovered(const io::PyramidLayout& layout, const io::PatchId& id);

}  // namespace terrain::runtime
