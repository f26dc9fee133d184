#include "terrain/io/NoDataFill.h"

#include "terrain/base/Assert.h"
#include "terrain/io/HeightCodes.h"

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

std::int64_t fillNoDataRow(std::span<float> row, std::span<std::uint8_t> valid,
                           const std::optional<VerticalTransform>& units) {
    TERRAIN_ASSERT(row.size() == valid.size());
    const auto n = static_cast<std::int64_t>(row.size());
    std::int64_t filled = 0;
    std::int64_t previousValid = -1;  // index of the last valid sample seen
    for (std::int64_t i = 0; i <= n; ++i) {
        const bool isValid = i < n && !std::isnan(row[i]);
        if (i < n) valid[i] = isValid ? 1 : 0;
        if (!isValid && i < n) continue;
        // Samples (previousValid, i) are a run of no-data between two valid ends (or an end).
        const std::int64_t runStart = previousValid + 1;
        if (i > runStart) {
            filled += i - runStart;
            for (std::int64_t k = runStart; k < i; ++k) {
                if (previousValid >= 0 && i < n) {
                    const double t = double(k - previousValid) / double(i - previousValid);
                    const double h = (1.0 - t) * row[previousValid] + t * row[i];
                    row[k] = units ? roundToSourceUnits(h, *units) : static_cast<float>(h);
                } else if (previousValid >= 0) {
                    row[k] = row[previousValid];
                } else if (i < n) {
                    row[k] = row[i];
                } else {
                    row[k] = 0.0f;
                }
            }
        }
        previousValid = i;
    }
    return filled;
}

}  // namespace terrain::io
