// ImageryTexelsPerPixel: percentiles of the figures with imagery, by rank in sorted order.
#include "terrain/runtime/ImageryTexelsPerPixel.h"

#include <algorithm>
#include <cmath>

namespace terrain::runtime {

ImageryTexelsPerPixel summariseTexelsPerPixel(std::vector<double> perPixel) {
    std::erase_if(perPixel, [](double t) { return !(t > 0.0); });  // NaN too
    ImageryTexelsPerPixel out;
    out.pixels = perPixel.size();
    if (perPixel.empty()) return out;
    std::sort(perPixel.begin(), perPixel.end());
    const auto rank = [&](double q) {
        const auto r =
            static_cast<std::size_t>(std::floor(q * static_cast<double>(perPixel.size())));
        return perPixel[std::min(r, perPixel.size() - 1)];
    };
    out.p5 = rank(0.05);
    out.p50 = rank(0.5);
    out.p95 = rank(0.95);
    const auto inRange = std::count_if(perPixel.begin(), perPixel.end(), [](double t) {
        return t >= ImageryTexelsPerPixel::kLowest && t <= ImageryTexelsPerPixel::kHighest;
    });
    out.inRange = static_cast<double>(inRange) / static_cast<double>(perPixel.size());
    return out;
}

ImageryTexelsPerPixel summariseTexelsPerPixel(std::span<const float> perPixel) {
    return summariseTexelsPerPixel(std::vector<double>(perPixel.begin(), perPixel.end()));
}

}  // namespace terrain::runtime
