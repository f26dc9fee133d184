#include "terrain/build/NoDataFill.h"

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

std::int64_t fillNoDataRow(std::span<float> row, std::span<std::uint8_t> valid,
                           const std::optional<VerticalTransform>& units) {
    return fillNoDataWindow(row, valid, units, std::nullopt, std::nullopt);
}

std::int64_t fillNoDataWindow(std::span<float> row, std::span<std::uint8_t> valid,
                              const std::optional<VerticalTransform>& units,
                              std::optional<RowNeighbour> west, std::optional<RowNeighbour> east) {
    TERRAIN_ASSERT(row.size() == valid.size());
    const auto n = static_cast<std::int64_t>(row.size());
    TERRAIN_ASSERT(!west || west->offset < 0);
    TERRAIN_ASSERT(!east || east->offset >= n);
    std::int64_t filled = 0;
    std::optional<RowNeighbour> previous = west;  // the last valid sample seen
    for (std::int64_t i = 0; i <= n; ++i) {
        const bool isValid = i < n && !std::isnan(row[i]);
        if (i < n) valid[i] = isValid ? 1 : 0;
        if (!isValid && i < n) continue;
        // Samples (previous, next) are a run of no-data between two valid ends (or an end).
        const std::optional<RowNeighbour> next =
            i < n ? std::optional<RowNeighbour>{{i, row[i]}} : east;
        const std::int64_t runStart =
            previous ? std::max<std::int64_t>(previous->offset + 1, 0) : 0;
        if (i > runStart) {
            filled += i - runStart;
            for (std::int64_t k = runStart; k < i; ++k) {
                if (previous && next) {
                    const double t =
                        double(k - previous->offset) / double(next->offset - previous->offset);
                    const double h = (1.0 - t) * previous->value + t * next->value;
                    row[k] = units ? roundToSourceUnits(h, *units) : static_cast<float>(h);
                } else if (previous) {
                    row[k] = previous->value;
                } else if (next) {
                    row[k] = next->value;
                } else {
                    row[k] = 0.0f;
                }
            }
        }
        if (i < n) previous = RowNeighbour{i, row[i]};
    }
    return filled;
}

}  // namespace terrain::io
