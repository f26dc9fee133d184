// GroundHeight: a cheap, conservative height of the ground under a world x, y from what is
// resident on the GPU, for flight controls (speed that scales with height above ground, a
// floor the camera keeps above) and flights that hug the terrain.
#pragma once

#include "terrain/runtime/TerrainGeometry.h"
#include "terrain/runtime/TileResidency.h"

namespace terrain::runtime {

/// The maximum height of the finest resident patch under (x, y), metres: at or above the
/// real ground there, so a camera kept above it never enters the terrain. Outside the DEM,
/// or before the root is resident, the DEM's highest point. O(levels). Render thread only.
double conservativeGroundHeight(const TileResidency& residency, const TerrainGeometry& geometry,
                                double x, double y);

}  // namespace terrain::runtime
