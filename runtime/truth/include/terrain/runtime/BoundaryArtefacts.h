// BoundaryArtefacts: pixels on patch boundaries that the draw got wrong on its own (issue 46,
// "boundary artefacts"): a pixel where two patches meet whose colour differs from both of its
// neighbours across the boundary and from the reference image. A pinhole where two patches'
// edges do not quite meet shows the sky or the far side of the globe there; a shading step
// that the reference has too is not one. Where the boundaries lie comes from the patch-id view
// (TerrainDebugView::PatchId). Pure CPU functions of images of equal size, any row order (the
// same in every argument).
#pragma once

#include "terrain/runtime/FrameImages.h"

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace terrain::runtime {

/// The patch-id view's pixels (RGBA8) decoded: draw instance + 1, 0 where no patch drew.
std::vector<std::uint32_t> patchIdsOf(std::span<const std::uint8_t> patchViewRgba);

struct BoundaryArtefacts {
    /// Default threshold: the largest R, G or B difference, 8-bit levels, above which two
    /// colours differ (a step a viewer sees; fog and shading vary far less between adjacent
    /// pixels of one surface).
    static constexpr int kDefaultThresholdLevels = 32;

    /// Two depths (reversed Z, near / distance) within this relative difference are one
    /// surface's.
    static constexpr double kSameSurface = 0.05;

    /// A pixel q lies on a silhouette (an occluding edge, or a crest sharp enough to look
    /// like one) where its depth's second difference along a row or a column, relative to
    /// its depth, exceeds this: reversed Z is affine in screen space across a plane, so its
    /// second difference is 0 on a plane, about 1e-5 to 1e-4 of the depth on rough ground
    /// seen obliquely, and 5e-3 or more where one surface occludes another (Puget Sound and
    /// Rainier benches, issue 46). A pixel beside one that draws nothing is on one too.
    static constexpr double kSilhouetteCurvature = 2e-3;

    std::uint64_t boundaryPixels = 0;  ///< pixels with a neighbour (4-connected) of another patch
    std::vector<std::size_t> pixels;   ///< the artefacts' pixel indices, ascending
    /// Edge pixels that stand out as an artefact would but lie at a silhouette, where the
    /// reference cannot tell a wrong shade from the LOD's own error (not artefacts; reported
    /// so that what the detector cannot judge is seen).
    std::uint64_t silhouettePixels = 0;
};

/// Pixel i of an image `width` pixels wide has a 4-neighbour of another patch (`patchIds`,
/// patchIdsOf a patch-id view).
bool onPatchBoundary(std::span<const std::uint32_t> patchIds, int width, std::size_t i);

/// The boundary artefacts of `lod` against `reference` (same camera and size): pixel p with
/// neighbours a and b on either side of it along a row or a column, p's patch differing from
/// a's or b's (p lies on a boundary along that line), and p's colour differing by more than
/// `thresholdLevels` (R, G or B) from a's, from b's and from the reference's p; and either
///  - p belongs to neither a's patch nor b's and lies farther than both (depths more than
///    kSameSurface apart): a sliver between them, the sky or a farther surface seen through a
///    gap (a pinhole, whatever its colour); a third patch between a nearer and a farther side
///    is a silhouette's layers, not a gap; or
///  - p shows the reference's surface there (depths within kSameSurface) and a and b match
///    the reference's colours: p's colour alone is wrong (shading at the patch's edge). Where
///    the sides differ from the reference too, the LOD's detail differs (a coarser level's
///    shading, aliasing): not the boundary's doing;
/// and, in the second case, no silhouette (kSilhouetteCurvature) in either image within
/// max(1, shiftPx) of p (the LOD may move an occluding edge or a crest up to ε pixels, and
/// the pixel on it shows whichever side, or the crest's own shading, by where the edge
/// falls inside it: counted in silhouettePixels instead); and no reference pixel within
/// `shiftPx` of p (rows and columns) has p's colour. Where the reference shows it that near,
/// the LOD drew that surface up to shiftPx off (its error, within ε when shiftPx is ε
/// rounded up): on detailed ground a pixel then differs from its neighbours and from the
/// reference's p, and a silhouette's notch shows the sky, without anything wrong at the
/// boundary.
/// A silhouette the LOD draws a pixel off the reference's shows another surface at p that
/// belongs to one side: the LOD's error within ε, not an artefact. `patchIds` is patchIdsOf
/// the same frame's patch-id view.
BoundaryArtefacts findBoundaryArtefacts(
    const FrameImages& lod, std::span<const std::uint32_t> patchIds, const FrameImages& reference,
    int shiftPx = 0, int thresholdLevels = BoundaryArtefacts::kDefaultThresholdLevels);

}  // namespace terrain::runtime
