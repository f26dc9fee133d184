// ImageComparison: the image measures of accuracy (docs/accuracy.md): RMSE and PSNR of the
// shaded LOD image against the reference image, crack pixels (the clear colour showing
// where the reference shows terrain), and temporal popping (how much the LOD image changes
// between consecutive frames beyond what the reference image changes). Pure CPU functions
// of RGBA8 images of equal size (any row order, the same in every argument).
#pragma once

#include "terrain/runtime/FrameImages.h"

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace terrain::runtime {

/// PSNR reported for identical images (RMSE 0), so the figure stays a finite number.
inline constexpr double kIdenticalPsnrDb = 100.0;

struct ImageDifference {
    double rmse = 0.0;  ///< over the R, G, B channels of every pixel, 8-bit levels (0–255)
    double psnrDb = kIdenticalPsnrDb;  ///< 20 · log10(255 / rmse), kIdenticalPsnrDb when rmse = 0
};

/// RMSE and PSNR of `a` against `b` (RGBA8, alpha ignored).
ImageDifference compareImages(std::span<const std::uint8_t> a, std::span<const std::uint8_t> b);

struct UncoveredPixels {
    /// Pixels where the LOD shows the clear colour but the reference drew terrain: cracks,
    /// holes, and silhouettes the LOD draws lower than the full-resolution terrain.
    std::uint64_t uncovered = 0;
    /// The uncovered pixels enclosed by terrain: not 4-connected, through pixels of the
    /// clear colour in the LOD image, to a pixel where neither image shows terrain (the
    /// sky, seen past a silhouette). Cracks between patches and holes; a silhouette that
    /// is drawn too low is connected to the sky above it and is not counted here, nor is a
    /// pixel whose only way to the sky is through a corner (a notch of a silhouette askew to
    /// the pixel grid; one step, so a diagonal crack line counts but for its last pixel).
    /// Pixel indices, rows bottom-up.
    std::vector<std::size_t> cracks;
};

/// Compares what `lod` covers (its pixels of `clearRgb` are uncovered) with what
/// `reference` drew (its depth > 0). Image borders are not sky: a clear region touching
/// them counts as a crack unless it also reaches real sky.
UncoveredPixels countUncoveredPixels(const FrameImages& lod, const FrameImages& reference,
                                     const std::array<std::uint8_t, 3>& clearRgb);

/// Pixels where the LOD drew terrain (depth > 0) and the reference drew none within
/// `shiftPx` of them (rows and columns): what the LOD adds beyond the truth's outline, which
/// the error measure cannot see (it compares pixels both drew) — a wall hanging below a data
/// edge, a skirt seen from beneath the surface, terrain beyond the data. The LOD may draw a
/// silhouette up to ε off the reference's, hence the allowance (⌈ε⌉).
std::uint64_t countOverdrawnPixels(const FrameImages& lod, const FrameImages& reference,
                                   int shiftPx);

/// Mean over pixels of the per-pixel change |a − b| (mean of the R, G, B differences),
/// 8-bit levels.
double meanImageChange(std::span<const std::uint8_t> a, std::span<const std::uint8_t> b);

/// The image change the LOD's own change between two frames makes, over the pixels where
/// both images show terrain: `held` is the previous frame's LOD drawn from the camera of
/// `drawn` (TerrainStyle::lodCamera). The camera is the same, so unlike poppingLevels no
/// motion is in it; pixels only one covers (the held LOD's patches culled by the previous
/// view) are not a switch and are left out.
struct LodSwitchChange {
    /// A change a viewer sees as a jump: more than this many 8-bit levels in one frame.
    static constexpr double kJumpLevels = 8.0;
    /// The mean per-pixel change (mean R, G, B difference), 8-bit levels. A change spread
    /// over frames (geomorphing) sums to the same as one jump, so this does not fall with
    /// it over a flight of many frames.
    double meanLevels = 0.0;
    /// The share of those pixels that change by more than kJumpLevels: the jumps
    /// geomorphing is for.
    double jumpShare = 0.0;
};
LodSwitchChange lodSwitchChange(const FrameImages& held, const FrameImages& drawn);

/// Temporal popping, 8-bit levels: the mean over pixels of
///   max(0, |L_t − L_{t−1}| − |R_t − R_{t−1}|)
/// with |·| the mean absolute R, G, B difference of one pixel: the change of the LOD image
/// L that the reference image R, rendered for the same two cameras, does not show (LOD
/// switches, streaming refinements). 0 for a LOD that changes exactly as the truth does.
double poppingLevels(std::span<const std::uint8_t> lodPrevious, std::span<const std::uint8_t> lod,
                     std::span<const std::uint8_t> referencePrevious,
                     std::span<const std::uint8_t> reference);

}  // namespace terrain::runtime
