// ErrorImageSummary: what ScreenSpaceErrorStats says about an image of per-pixel errors, the
// half the planar and the globe measurements share: the largest error two adjacent pixels both
// show (a lone pixel's error is the rasteriser's, docs/accuracy.md), the mean, the 99th
// percentile and where the worst pixel was; and how a skirt pixel is counted.
#pragma once

#include "terrain/runtime/ScreenSpaceError.h"

#include <glm/vec4.hpp>

#include <algorithm>
#include <cmath>
#include <span>
#include <vector>

namespace terrain::runtime {

/// `errorImage`: per pixel (rows bottom-up) the error, −1 where nothing was measured;
/// `measuredAt`: per pixel W_lod (xyz) and the reference height it was measured against (w);
/// `errors`: the measured errors (reordered); `sum`, `sumFixed`: their sums (primary, fixed
/// diagonal). Fills maxPx, worst*, meanPx, meanFixedDiagonalPx and p99Px of `stats`, whose
/// `pixels` must already be counted.
void summariseErrorImage(int width, int height, std::span<const float> errorImage,
                         std::span<const glm::dvec4> measuredAt, std::vector<double>& errors,
                         double sum, double sumFixed, ScreenSpaceErrorStats& stats);

/// Counts a skirt pixel of error `errorPx` (+∞ when its segment to the truth passes behind
/// the camera) in `stats`.
inline void countSkirtPixel(ScreenSpaceErrorStats& stats, double errorPx) {
    ++stats.skirtPixels;
    if (std::isfinite(errorPx)) {
        stats.skirtMaxPx = std::max(stats.skirtMaxPx, errorPx);
    } else {
        ++stats.skirtUnboundedPixels;
    }
}

}  // namespace terrain::runtime
