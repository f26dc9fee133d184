// GlobeDrawnGround: a height at or above the ground under a point, from what is at hand
// without a read: the frame's draw list, or the resident patches and the CPU cache's tiles.
// The viewer keeps the camera above it and the stress flight flies over it.
#pragma once

#include "terrain/globe/GlobePatch.h"
#include "terrain/pyramid/PatchRecord.h"
#include "terrain/pyramid/PyramidLayout.h"
#include "terrain/runtime/PatchDraw.h"
#include "terrain/runtime/Surface.h"

#include <glm/vec3.hpp>

#include <functional>
#include <optional>
#include <span>

namespace terrain::runtime {

/// The largest maxHeight of the drawn patches whose face square holds the nadir of `ecef`
/// (a patch edge belongs to both sides) and of the native tiles that own the ground there
/// (every native tile that owns all it covers); 0 (the ellipsoid) where none does, e.g. when
/// the nadir was culled.
double drawnGroundCeiling(std::span<const PatchDraw> draws, const glm::dvec3& ecef);

/// What is at hand for a patch without a read: its summary when its tile is resident on the
/// GPU (TileResidency::residentInfo), its tile when the CPU cache holds it; else null.
struct GlobeGroundLookup {
    std::function<const io::PatchInfo*(const globe::GlobePatchId&)> residentInfo;
    std::function<const io::PatchRecord*(const globe::GlobePatchId&)> cachedTile;
    /// A pyramid with native grids (docs/globe.md, "Native leaves"; optional): the native
    /// tile the LOD draws under the nadir in place of a finest patch of a (layout) level
    /// (Surface::nativeTileUnder), and its tile when the CPU cache holds it.
    std::function<std::optional<Surface::NativeTilePoint>(const glm::dvec3& up, int level)>
        nativeTileUnder;
    std::function<const io::PatchRecord*(const io::PatchId&)> cachedNativeTile;
};

/// The ground under the nadir of `ecef` as the finest resident data there draws it, to
/// within one sample: down the resident patches holding the nadir to the deepest, then the
/// highest of the four samples of its tile around the nadir (the surface drawn between them
/// lies at or below it, whatever its triangles, and close to the camera the LOD draws every
/// sample), or that patch's maxHeight when its tile is not in the CPU cache (or the four are
/// not finite). Where a native tile replaces that patch near the ground and its tile is in the
/// CPU cache, the highest of its four samples around the nadir instead: the surface drawn
/// there, which the face grid's resampling misses by up to its Err(P) (tens of metres on a
/// steep slope). 0, the bare ellipsoid, where not even the face's root is resident. Unlike a
/// draw list it does not depend on what the frame culled, so a camera below the ground (a
/// jump to an altitude under a mountain) still finds it.
double residentGroundHeight(const glm::dvec3& ecef, const io::PyramidLayout& layout,
                            const GlobeGroundLookup& lookup);

}  // namespace terrain::runtime
