// ScreenSpaceError: the screen-space geometric error the LOD actually shows, measured per
// pixel against the ground truth (docs/accuracy.md, "Measured screen-space error"; on the
// globe docs/globe.md). It is what ε promises (Yusov & Shevtsov 2011, §5): the projected
// length of the vertical segment between the drawn surface and the full-resolution surface.
//
// For every pixel the LOD drew, its depth (reversed Z, float) is unprojected in double to
// the camera-relative point W_lod of the drawn surface seen through the pixel's centre; the
// truth (TruthSurface.h: the plane's DEM, the globe's sources or finest level) gives a point
// W_ref on the vertical through it (the z axis, the ellipsoid's normal); both are projected
// and their distance in pixels is the pixel's error. The full-resolution mesh is ambiguous
// inside a cell (either diagonal; the GPU tessellator chooses its own, and the pyramid's
// bounds hold for both), so the primary figure takes the nearer of the two diagonals'
// heights (0 when W_lod lies between them); the stricter figure against one fixed diagonal
// (the reference renderer's own on the plane) is reported beside it.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/TruthSurface.h"

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace terrain::runtime {

/// One measured pixel whose error exceeds the threshold, for diagnosis and for tests that
/// check where the excess comes from.
struct PixelError {
    int x = 0;  ///< rows bottom-up
    int y = 0;
    glm::dvec3 world{0.0};  ///< W_lod, world metres
    double surfaceM = 0.0;  ///< the full-resolution height it was measured against
    double errorPx = 0.0;
};

struct ScreenSpaceErrorStats {
    /// At most this many pixels over the threshold are kept in overThreshold.
    static constexpr std::size_t kMaxKeptPixels = 65536;

    /// Pixels measured: drawn by the LOD's patch surface (not its skirts) where the
    /// reference also shows terrain.
    std::uint64_t pixels = 0;
    /// The primary measure (nearer diagonal), largest over pixels that agree with a
    /// neighbour: the largest error that two adjacent pixels both show (the larger of the
    /// smaller errors of every pair of 8-neighbours). A single pixel's error alone does not
    /// count here: the rasteriser interpolates depth on a triangle seen edge-on with float
    /// rounding the plane equation amplifies, and such a pixel's unprojection need not lie
    /// on any drawn triangle (docs/accuracy.md, "Rasterisation tolerance").
    double maxPx = 0.0;
    double maxSinglePixelPx = 0.0;  ///< the largest error of any one pixel, artefacts included
    /// The largest error of any one pixel without the horizontal tolerance: W_lod measured
    /// against the truth at exactly its own x, y. Above maxSinglePixelPx only where the
    /// surface is steep enough that a fraction of a pixel sideways is pixels vertically.
    double maxExactPositionPx = 0.0;
    double meanPx = 0.0;                    ///< mean over pixels (0 when none)
    double p99Px = 0.0;                     ///< 99th percentile over pixels
    std::uint64_t pixelsOverThreshold = 0;  ///< pixels whose error exceeds the given threshold
    std::vector<PixelError> overThreshold;  ///< the first kMaxKeptPixels of them
    double maxFixedDiagonalPx = 0.0;        ///< against the reference mesh's diagonal only
    double meanFixedDiagonalPx = 0.0;

    /// Pixels drawn by skirts (the LOD depth differs from its skirtless draw): not surface,
    /// so not in the figures above; their own largest error is here.
    std::uint64_t skirtPixels = 0;
    double skirtMaxPx = 0.0;
    /// Skirt pixels whose segment to the truth passes behind the camera (a skirt hanging
    /// far below terrain that rises above a camera close by): their distance is unbounded,
    /// so they are left out of skirtMaxPx.
    std::uint64_t skirtUnboundedPixels = 0;
    /// Surface pixels whose x, y lies beyond the DEM's extent, more than a pixel from its
    /// edge: terrain the LOD draws where the DEM has none (patches overhanging its edge).
    std::uint64_t outsidePixels = 0;
    /// Pixels whose unprojection or error was NaN, or whose W_ref lies behind the camera.
    std::uint64_t nonFinitePixels = 0;
    /// Measured pixels whose comparison figure (the fixed diagonal's height, or the exact
    /// position's) lies behind the camera, so its projected distance is unbounded: a needle
    /// seen from beside its tip, whose fixed-diagonal height is far below. Left out of
    /// maxFixedDiagonalPx, meanFixedDiagonalPx and maxExactPositionPx; the error itself
    /// (maxPx) was measured.
    std::uint64_t unboundedComparisonPixels = 0;

    /// Where maxPx was found (a pixel of that pair): pixel (rows
    /// bottom-up), W_lod in world metres, and the full-resolution height it was measured
    /// against (nearer diagonal), for reports.
    int worstX = -1;
    int worstY = -1;
    glm::dvec3 worstWorld{0.0};
    double worstReferenceM = 0.0;
};

/// Measures the error of an LOD frame (depth images rows bottom-up, camera.viewportWidth ×
/// camera.viewportHeight). `lodDepth`: the LOD as drawn (with skirts); `lodDepthNoSkirts`:
/// the same frame drawn without skirts, to tell skirt pixels apart (empty: every drawn pixel
/// counts as surface); `referenceDepth`: the reference renderer's depth (empty: every drawn
/// pixel is measured). Each drawn point is measured against the truth's lowest and highest
/// heights within its horizontal tolerance (TruthSurface::horizontalTolerancePx). Errors:
/// truth that cannot be read.
Result<ScreenSpaceErrorStats> measureScreenSpaceError(const Camera& camera,
                                                      std::span<const float> lodDepth,
                                                      std::span<const float> lodDepthNoSkirts,
                                                      std::span<const float> referenceDepth,
                                                      TruthSurface& truth, double thresholdPx);

}  // namespace terrain::runtime
