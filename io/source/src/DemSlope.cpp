#include "terrain/source/DemSlope.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace terrain::io {

namespace {

constexpr std::int64_t kRowPairs = 32;
constexpr std::int64_t kMaxColumns = 2048;
constexpr double kMetresPerDegree = 6378137.0 * std::numbers::pi / 180.0;

void horizontalSpacing(const DemInfo& info, DemSlopeSample& out) {
    if (!info.hasGeoreference) return;  // 1 m per sample, as the builder takes it
    const Georeference& g = info.georeference;
    switch (g.crsKind) {
        case CrsKind::Projected:
            out.metresPerColumn = g.pixelSizeX;
            out.metresPerRow = g.pixelSizeY;
            return;
        case CrsKind::Geographic: {
            const double centreLatitude = g.originY - 0.5 * g.pixelSizeY * double(info.height);
            const double cosLatitude =
                std::max(std::cos(centreLatitude * std::numbers::pi / 180.0), 1e-3);
            out.metresPerColumn = g.pixelSizeX * kMetresPerDegree * cosLatitude;
            out.metresPerRow = g.pixelSizeY * kMetresPerDegree;
            return;
        }
        case CrsKind::Unknown:
            return;
    }
}

}  // namespace

Result<DemSlopeSample> sampleSlopes(DemReader& reader) {
    const DemInfo& info = reader.info();
    DemSlopeSample out;
    horizontalSpacing(info, out);
    if (info.width < 2 || info.height < 2) return out;
    const std::int64_t columns = std::min(info.width, kMaxColumns);
    const std::int64_t x0 = (info.width - columns) / 2;
    const std::int64_t pairsOfRows = std::min(kRowPairs, info.height - 1);
    std::vector<float> rows(static_cast<std::size_t>(2 * columns));
    std::vector<double> slopes;
    slopes.reserve(static_cast<std::size_t>(pairsOfRows * columns * 3));
    const auto add = [&](float a, float b, double distance) {
        if (std::isfinite(a) && std::isfinite(b))
            slopes.push_back(std::abs(double(a) - double(b)) / distance);
    };
    for (std::int64_t i = 0; i < pairsOfRows; ++i) {
        // Spread evenly from the first to the last pair of rows.
        const std::int64_t y = pairsOfRows == 1 ? 0 : i * (info.height - 2) / (pairsOfRows - 1);
        if (Status s = reader.readWindow(x0, y, columns, 2, rows); !s) return s.error();
        const float* top = rows.data();
        const float* below = top + columns;
        for (std::int64_t x = 0; x < columns; ++x) {
            if (x + 1 < columns) {
                add(top[x], top[x + 1], out.metresPerColumn);
                add(below[x], below[x + 1], out.metresPerColumn);
            }
            add(top[x], below[x], out.metresPerRow);
        }
    }
    out.pairs = slopes.size();
    if (slopes.empty()) return out;
    const auto middle = slopes.begin() + std::ptrdiff_t(slopes.size() / 2);
    std::nth_element(slopes.begin(), middle, slopes.end());
    out.medianSlope = *middle;
    return out;
}

std::optional<std::string> absurdReliefWarning(const DemInfo& info, const DemSlopeSample& slopes) {
    if (slopes.pairs == 0 || !(slopes.medianSlope > kAbsurdMedianSlope)) return std::nullopt;
    const double degrees = std::atan(slopes.medianSlope) * 180.0 / std::numbers::pi;
    return fmt::format(
        "{}: the median slope between adjacent samples is {:.3g} ({:.1f}°) with samples {:g} m "
        "× {:g} m apart and heights × {:g}: steeper than any real terrain, so the horizontal "
        "spacing or the height unit is probably wrong (it would draw as needles). Give the "
        "true spacing with --spacing METRES (or the CRS with --epsg CODE), and metres per "
        "height unit with --vertical-scale (e.g. 0.1 for decimetres)",
        info.path, slopes.medianSlope, degrees, slopes.metresPerColumn, slopes.metresPerRow,
        info.vertical.scale);
}

}  // namespace terrain::io
