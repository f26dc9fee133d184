#include "SourceSlopes.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace terrain::io {

namespace {

// A histogram of the slope's angle, a hundredth of a degree a bin: one pass, no copy of the
// samples.
class SlopeHistogram {
public:
    void add(double slope) {
        const double degrees = std::atan(slope) / kDegree;
        ++m_bins[static_cast<std::size_t>(std::ceil(degrees * kBinsPerDegree))];
        ++m_count;
    }
    double percentile(double share) const {
        if (m_count == 0) return 0.0;
        const auto wanted = static_cast<std::int64_t>(std::ceil(share * double(m_count)));
        std::int64_t below = 0;
        for (std::size_t bin = 0; bin < m_bins.size(); ++bin) {
            below += m_bins[bin];
            if (below >= wanted) return std::tan(double(bin) / kBinsPerDegree * kDegree);
        }
        return std::tan(double(m_bins.size() - 1) / kBinsPerDegree * kDegree);
    }

private:
    static constexpr int kBinsPerDegree = 100;
    // Up to 89.99°: a vertical step between two samples is no slope a tangent can hold.
    std::vector<std::int64_t> m_bins = std::vector<std::int64_t>(90 * kBinsPerDegree, 0);
    std::int64_t m_count = 0;
};

// Rows or columns skipped between the pairs measured, so about 2^20 are.
std::int64_t strideFor(std::int64_t pairs) {
    constexpr double kPairs = double(1 << 20);
    return std::max<std::int64_t>(
        1, static_cast<std::int64_t>(std::ceil(std::sqrt(double(pairs) / kPairs))));
}

}  // namespace

SourceSlopes::SourceSlopes(const GeographicGrid& grid, double share, double longestPixels) {
    const std::int64_t width = grid.width(), height = grid.height();
    const auto valid = [&](std::int64_t col, std::int64_t row) { return grid.validAt(col, row); };
    const auto h = [&](std::int64_t col, std::int64_t row) {
        return double(grid.heightAt(col, row));
    };
    {
        SlopeHistogram histogram;
        const std::int64_t stride = strideFor(width * height);
        for (std::int64_t row = 1; row + 1 < height; row += stride) {
            const double latitude = grid.latitudeOf(row);
            const double dx = 2.0 * grid.eastWestMetres(latitude);
            const double dy = 2.0 * grid.northSouthMetres(latitude);
            for (std::int64_t col = 1; col + 1 < width; col += stride) {
                if (!valid(col, row) || !valid(col - 1, row) || !valid(col + 1, row) ||
                    !valid(col, row - 1) || !valid(col, row + 1))
                    continue;
                histogram.add(std::hypot((h(col + 1, row) - h(col - 1, row)) / dx,
                                         (h(col, row + 1) - h(col, row - 1)) / dy));
            }
        }
        m_gradient = histogram.percentile(share);
    }
    // Baselines from a pixel up, by factors of √2.
    for (double pixels = 1.0; pixels < longestPixels * std::sqrt(2.0); pixels *= std::sqrt(2.0))
        m_baselines.push_back(std::round(pixels));
    m_baselines.erase(std::unique(m_baselines.begin(), m_baselines.end()), m_baselines.end());
    for (const double baseline : m_baselines) {
        const auto k = static_cast<std::int64_t>(baseline);
        SlopeHistogram eastWest, northSouth;
        const std::int64_t stride = strideFor(width * height);
        for (std::int64_t row = 0; row < height; row += stride) {
            const double latitude = grid.latitudeOf(row);
            const double lx = double(k) * grid.eastWestMetres(latitude);
            const double ly = double(k) * grid.northSouthMetres(latitude);
            for (std::int64_t col = 0; col < width; col += stride) {
                if (!valid(col, row)) continue;
                if (col + k < width && valid(col + k, row))
                    eastWest.add(std::abs(h(col + k, row) - h(col, row)) / lx);
                if (row + k < height && valid(col, row + k))
                    northSouth.add(std::abs(h(col, row + k) - h(col, row)) / ly);
            }
        }
        m_eastWest.push_back(std::min(m_gradient, eastWest.percentile(share)));
        m_northSouth.push_back(std::min(m_gradient, northSouth.percentile(share)));
    }
}

double SourceSlopes::over(bool eastWest, double pixels) const {
    const std::vector<double>& slopes = eastWest ? m_eastWest : m_northSouth;
    if (slopes.empty()) return m_gradient;
    if (pixels <= m_baselines.front()) return slopes.front();
    if (pixels >= m_baselines.back()) return slopes.back();
    const auto above = static_cast<std::size_t>(
        std::upper_bound(m_baselines.begin(), m_baselines.end(), pixels) - m_baselines.begin());
    const double l0 = std::log(m_baselines[above - 1]), l1 = std::log(m_baselines[above]);
    const double f = (std::log(pixels) - l0) / (l1 - l0);
    return (1.0 - f) * slopes[above - 1] + f * slopes[above];
}

}  // namespace terrain::io
