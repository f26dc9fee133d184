// NativeOwnership: where a native tile owns the ground (docs/globe.md, "Native leaves"). A
// native tile is drawn once for the face patches that split into it, but its outline follows
// its source's grid, not the faces', so it reaches past them over face patches that drew
// themselves. Both surfaces are within their bounds there, yet not the same surface: drawn
// both, each pixel took the nearer of the two and their shading interleaved in blotches
// (ETOPO20 + Rainier at 7 km: 2.46 levels of shading seam against 0.87 without native
// tiles). The face patches it stands for own the ground; the tile draws only over them.
#pragma once

#include "terrain/runtime/PatchDraw.h"

#include <span>

namespace terrain::runtime {

/// Sets `draw`'s imageryPatch, nativeCells and nativeWindow from the face patches (layout
/// ids) that split into it (at least one; in view or not), in any order: the cells are those
/// of the finest of them, the patch it then drapes. Leaves nativeCells 0 (owns all it covers)
/// where they lie on more than one cube face or span more than 8 cells of that level.
/// Allocates nothing.
void assignNativeOwnership(PatchDraw& draw, std::span<const io::PatchId> holders);

/// Whether face coordinates (u, v) on `draw`'s imageryPatch (in patches of its level from its
/// corner) lie on ground it owns: the CPU twin of shaders/surface_globe.glsl's
/// surfaceOwnsGround.
bool nativeTileOwns(const PatchDraw& draw, double u, double v);

}  // namespace terrain::runtime
