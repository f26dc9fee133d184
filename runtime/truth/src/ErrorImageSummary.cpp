#include "ErrorImageSummary.h"

#include <algorithm>
#include <cmath>

namespace terrain::runtime {

void summariseErrorImage(int w, int h, std::span<const float> errorImage,
                         std::span<const glm::dvec4> measuredAt, std::vector<double>& errors,
                         double sum, double sumFixed, ScreenSpaceErrorStats& stats) {
    // The largest error two adjacent pixels both show: for every pixel, the smaller of its
    // own error and its largest measured 8-neighbour's.
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(w) +
                                  static_cast<std::size_t>(x);
            if (errorImage[i] < 0.0f) continue;
            float neighbour = -1.0f;
            for (int j = std::max(y - 1, 0); j <= std::min(y + 1, h - 1); ++j) {
                for (int k = std::max(x - 1, 0); k <= std::min(x + 1, w - 1); ++k) {
                    if (j == y && k == x) continue;
                    neighbour = std::max(
                        neighbour,
                        errorImage[static_cast<std::size_t>(j) * static_cast<std::size_t>(w) +
                                   static_cast<std::size_t>(k)]);
                }
            }
            if (neighbour < 0.0f) continue;  // a lone measured pixel shows nothing twice
            const double shared =
                std::min(static_cast<double>(errorImage[i]), static_cast<double>(neighbour));
            if (shared > stats.maxPx || stats.worstX < 0) {
                stats.maxPx = shared;
                stats.worstX = x;
                stats.worstY = y;
                stats.worstWorld = glm::dvec3(measuredAt[i]);
                stats.worstReferenceM = measuredAt[i].w;
            }
        }
    }
    if (stats.pixels > 0) {
        const auto n = static_cast<double>(stats.pixels);
        stats.meanPx = sum / n;
        const auto bounded = static_cast<double>(stats.pixels - stats.unboundedComparisonPixels);
        stats.meanFixedDiagonalPx = bounded > 0.0 ? sumFixed / bounded : 0.0;
        const auto rank = static_cast<std::size_t>(std::ceil(0.99 * n)) - 1;
        std::nth_element(errors.begin(), errors.begin() + static_cast<std::ptrdiff_t>(rank),
                         errors.end());
        stats.p99Px = errors[rank];
    }
}

}  // namespace terrain::runtime
