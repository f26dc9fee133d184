// EdgeTessellation: the CPU reference, in double, of the fine-grain LOD the terrain's
// tessellation control stage runs (shaders/terrain.tesc; Yusov & Shevtsov 2011, §5,
// "Fine-Grain Level of Detail Selection"): per block edge, the largest simplification d
// whose edge error still projects below ε, and the factors that follow from it.
//
// One deviation from §5, for a guaranteed bound: Yusov projects Λ_ec(d) at the edge's
// centre e_c only, an estimate that the block's points nearer the camera exceed (up to 3×
// at 1 m over a slope, docs/accuracy.md). Here Λ_ec(d) is projected by an upper bound over
// the box of the blocks sharing the edge (verticalErrorPxPerM), so the chosen d holds for
// every point of both blocks, and so does the inner level, the coarsest edge's. The
// tessellator's transition strips between finer edges and that inner level are charged
// to it too: the pyramid's λ(d) covers them (io::transitionErrors). A second deviation,
// for fewer triangles: the inner level may be coarser than every edge, where the block's
// own Λ(d) over its own box allows it (the inner mesh touches no neighbour).
//
// Vertex → domain mapping of a block primitive (the vertex stage's corners): u runs east
// along the patch's columns, v south along its rows, so GL's outer levels are
// [0] the west edge (u = 0), [1] north (v = 0), [2] east (u = 1), [3] south (v = 1).
#pragma once

#include "terrain/pyramid/PatchErrors.h"
#include "terrain/pyramid/PatchRecord.h"
#include "terrain/runtime/Aabb.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/TerrainGeometry.h"

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <vector>

namespace terrain::runtime {

struct BlockFactors {
    std::array<int, 4> outer{};  ///< GL order: west (u = 0), north (v = 0), east, south
    /// Both the same: the minimum of outer (Yusov §5), or coarser where the block's own
    /// Λ(d), projected over its own box, stays below ε (innerProjectedPx).
    std::array<int, 2> inner{};
    std::array<int, 4> simplification{};  ///< d of each edge, 0 (full resolution) … 4
    /// Λ_ec(d) of each edge at its d (Err(P) at d = 0), metres: how far the drawn edge may
    /// lie from the full-resolution surface; a skirt drops this plus the skirt depth.
    std::array<double, 4> edgeErrorM{};
    /// Λ_ec(d) · verticalErrorPxPerM of the edge's box for d = 1..4, pixels: the most any
    /// vertical error of Λ_ec(d) in the box may measure on screen; what d was chosen from.
    std::array<std::array<double, io::kMaxSimplification>, 4> projectedPx{};
    /// The block's own Λ(d) · verticalErrorPxPerM of its own box for d = 1..4, pixels:
    /// what an inner level coarser than every edge is chosen from.
    std::array<double, io::kMaxSimplification> innerProjectedPx{};
    /// The control stage discards the block (wholly beyond the DEM, or outside the view).
    bool culled = false;
};

/// An upper bound, in pixels per metre, on the on-screen length of any vertical segment
/// lying in `box` (camera-relative metres), seen through `relativeViewProjection` (Camera:
/// w_clip is the depth, z_clip the near plane's distance) on a viewport of `viewportPx`.
///
/// Why it bounds: along p(t) = p + t·e_z the clip position moves by a = M·e_z, so NDC
/// X = x/w moves at (a.x − X·a.w)/w, and the pixel position at
/// |((a.x − X·a.w)·W/2, (a.y − Y·a.w)·H/2)| / w per metre. The numerator is convex in
/// (X, Y), so its largest value over the rectangle of NDC the box covers (the hull of its
/// corners' projections, within the screen) is at a corner of that rectangle; the depth w
/// of a drawn point is at least the box's smallest corner depth, the near plane's, and its
/// distance over √(1 + tan²x + tan²y) (a box reaching behind the camera may lie far in
/// front of it where it is in view).
double verticalErrorPxPerM(const glm::dmat4& relativeViewProjection, const glm::dvec2& viewportPx,
                           const Aabb& box);

/// The world box of blocks first..last (inclusive) of patch `id`: their footprint, heights
/// lowM..highM (the control stage's blocksBoxM, in double).
Aabb blocksWorldBox(const TerrainGeometry& geometry, const io::PatchId& id, glm::ivec2 first,
                    glm::ivec2 last, double lowM, double highM);

/// The factors of every block of `record`'s patch seen by `camera` at ε = errorPx,
/// row-major by block (blocksPerSide² entries). Err(P) is record.info.error.
std::vector<BlockFactors> patchBlockFactors(const Camera& camera, const TerrainGeometry& geometry,
                                            const io::PatchRecord& record, double errorPx);

}  // namespace terrain::runtime
