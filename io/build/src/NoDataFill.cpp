#include "terrain/build/NoDataFill.h"

#include "VoidFill.h"

#include "terrain/base/Assert.h"
#include "terrain/pyramid/HeightCodes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string_view>

namespace terrain::io {
std::optional<VerticalTransform> wholeSourceUnits(const DemInfo& info) {
    constexpr std::array<std::string_view, 8> kIntegerTypes = {
        "uint8", "int8", "uint16", "int16", "uint32", "int32", "uint64", "int64"};
    const bool integer = std::find(kIntegerTypes.begin(), kIntegerTypes.end(), info.sampleType) !=
                         kIntegerTypes.end();
    if (!integer || info.resampledFrom || !(info.vertical.scale != 0.0) ||
        !std::isfinite(info.vertical.scale) || !std::isfinite(info.vertical.offset))
        return std::nullopt;
    return info.vertical;
}

std::int64_t fillNoData(std::int64_t width, std::int64_t height, std::span<float> heights,
                        std::span<std::uint8_t> valid,
                        const std::optional<VerticalTransform>& units,
                        const SurfaceBeneath* beneath) {
    TERRAIN_ASSERT(heights.size() == static_cast<std::size_t>(width * height));
    TERRAIN_ASSERT(valid.size() == heights.size());
    const std::int64_t missing = detail::markValidSamples(heights, valid);
    if (missing == 0) return 0;
    const detail::VoidFill::ReadWindow read = [&](std::int64_t x0, std::int64_t y0, std::int64_t w,
                                                  std::int64_t rows,
                                                  std::span<float> out) -> Status {
        for (std::int64_t r = 0; r < rows; ++r)
            std::copy_n(heights.begin() + static_cast<std::ptrdiff_t>((y0 + r) * width + x0), w,
                        out.begin() + static_cast<std::ptrdiff_t>(r * w));
        return {};
    };
    Result<detail::VoidFill> found = detail::VoidFill::find(width, height, read, beneath);
    TERRAIN_ASSERT(found.ok(), "reading a raster in memory cannot fail");
    // Every void was solved by find: writing the raster now changes nothing it reads.
    for (std::int64_t y = 0; y < height; ++y)
        for (std::int64_t x = 0; x < width; ++x) {
            const auto i = static_cast<std::size_t>(y * width + x);
            if (valid[i]) continue;
            const float h = found.value().at(x, y, beneath);
            heights[i] = units ? roundToSourceUnits(h, *units) : h;
        }
    return missing;
}

}  // namespace terrain::io
