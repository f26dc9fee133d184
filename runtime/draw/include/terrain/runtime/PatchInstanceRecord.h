// PatchInstanceRecord: the per-instance record of the planar patch draws (std430
// PatchInstance in shaders/terrain_patches.glsl), shared by every renderer that draws the
// LOD's patches from the GPU tile pool (TerrainRenderer, ValdetaroRenderer, LivnyRenderer),
// and the one function that fills them relative to the camera's anchor sample.
#pragma once

#include "terrain/cache/GpuTilePool.h"
#include "terrain/pyramid/PyramidLayout.h"
#include "terrain/runtime/PatchSelection.h"

#include <glm/vec2.hpp>

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace terrain::runtime {

struct alignas(16) PatchInstanceRecord {
    /// x, y: the patch's north-west sample minus the anchor (DEM samples); z: DEM samples
    /// per patch sample.
    std::array<float, 4> originAndStep;
    std::array<float, 4> errors;             ///< Err(P), skirt depth, min and max height, metres
    std::array<std::int32_t, 4> layerLevel;  ///< layer, level, the patch's x and y
    /// x: quads along a coarse cell's side, 0 when the patch is drawn as blocks; y: the cells'
    /// Λ, metres (CoarseCells.h). Only the terrain draw reads it; the records start as blocks.
    std::array<float, 4> coarseCells;
};
static_assert(sizeof(PatchInstanceRecord) == 64);

/// The records of `patches` (every one resident in `pool` on its layer, TERRAIN_ASSERT),
/// origins relative to `anchor` (setCameraFrameUniforms), into `out` (cleared first).
void writePatchInstanceRecords(const io::PyramidLayout& layout, const cache::GpuTilePool& pool,
                               std::span<const PatchDraw> patches, glm::dvec2 anchor,
                               std::vector<PatchInstanceRecord>& out);

}  // namespace terrain::runtime
