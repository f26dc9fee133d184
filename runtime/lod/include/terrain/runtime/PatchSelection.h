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
#include "terrain/runtime/PatchDraw.h"
#include "terrain/runtime/PlaneSurface.h"
#include "terrain/runtime/TerrainGeometry.h"
#include "terrain/runtime/TileResidency.h"

#include <cstdint>
#include <vector>

namespace terrain::runtime {

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

}  // namespace terrain::runtime
