// BoundaryShading: shading discontinuities along patch boundaries (issue 46, detector 6b): how
// much more the LOD's brightness steps between two neighbouring pixels of different patches
// than the reference's steps between the same two pixels, against the same figure for
// neighbouring pixels of one patch. A seam where patch levels meet (the two sides shaded
// from different levels' normals), or a patch edge shaded apart from its neighbour, steps
// where the reference does not; detail the LOD draws a pixel off, or aliases, steps inside
// patches as much as across their edges, so the interior figure is the control the boundary
// one is read against. Pure CPU functions of images of equal size, any row order.
#pragma once

#include "terrain/runtime/FrameImages.h"

#include <cstdint>
#include <span>

namespace terrain::runtime {

struct BoundaryShading {
    /// Pairs of 4-neighbouring pixels compared: of two patches (a boundary), of one patch.
    std::uint64_t boundaryPairs = 0;
    std::uint64_t interiorPairs = 0;
    /// Mean over the pairs of max(0, |ΔY_lod| − |ΔY_reference|), Y the pixels' luma (8-bit
    /// levels, Rec. 601): the step the LOD adds between the two pixels. 0 without pairs.
    double boundaryExcessLevels = 0.0;
    double interiorExcessLevels = 0.0;

    /// What patch boundaries add to the shading's steps over what the LOD's detail adds
    /// everywhere: boundaryExcessLevels − interiorExcessLevels (0 without boundary pairs).
    double seamLevels() const {
        return boundaryPairs > 0 ? boundaryExcessLevels - interiorExcessLevels : 0.0;
    }
};

/// The shading steps of `lod` against `reference` (same camera and size) over the pairs of
/// 4-neighbouring pixels that both images draw, on the reference's surface in both (depths
/// within BoundaryArtefacts::kSameSurface: a silhouette steps by nature), split by whether
/// patchIds (patchIdsOf the frame's patch-id view) differ.
BoundaryShading measureBoundaryShading(const FrameImages& lod,
                                       std::span<const std::uint32_t> patchIds,
                                       const FrameImages& reference);

}  // namespace terrain::runtime
