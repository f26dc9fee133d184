#include "MembraneFill.h"

#include "terrain/base/Assert.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace terrain::io::detail {
namespace {

struct Grid {
    std::int64_t width = 0, height = 0;
    std::vector<float> values;
    std::vector<std::uint8_t> fixed;
    std::size_t index(std::int64_t x, std::int64_t y) const {
        return static_cast<std::size_t>(y * width + x);
    }
};

// Red-black successive over-relaxation of the free cells: a cell's four neighbours within the
// grid (a missing one contributes nothing: no flux across the edge). ω is the optimal one of
// a square of the grid's larger side (Young's, 2 / (1 + sin(π/n))), which the coarse-to-fine
// start leaves with only the error of the finest scales to remove.
void relax(Grid& g, int maxSweeps) {
    const double n = double(std::max(g.width, g.height));
    const float omega = static_cast<float>(
        std::min(1.9, 2.0 / (1.0 + std::sin(std::numbers::pi / std::max(n, 2.0)))));
    for (int sweep = 0; sweep < maxSweeps; ++sweep) {
        float largest = 0.0f;
        for (int colour = 0; colour < 2; ++colour) {
            for (std::int64_t y = 0; y < g.height; ++y) {
                for (std::int64_t x = (y + colour) % 2; x < g.width; x += 2) {
                    const std::size_t i = g.index(x, y);
                    if (g.fixed[i]) continue;
                    float sum = 0.0f;
                    int count = 0;
                    if (x > 0) sum += g.values[i - 1], ++count;
                    if (x + 1 < g.width) sum += g.values[i + 1], ++count;
                    if (y > 0) sum += g.values[i - static_cast<std::size_t>(g.width)], ++count;
                    if (y + 1 < g.height)
                        sum += g.values[i + static_cast<std::size_t>(g.width)], ++count;
                    if (count == 0) continue;
                    const float change = omega * (sum / float(count) - g.values[i]);
                    g.values[i] += change;
                    largest = std::max(largest, std::abs(change));
                }
            }
        }
        if (largest <= kMembraneTolerance) return;
    }
}

// The grid halved: a coarse cell is fixed at the mean of its fixed fine cells, if it has any.
Grid coarsened(const Grid& fine) {
    Grid coarse;
    coarse.width = (fine.width + 1) / 2;
    coarse.height = (fine.height + 1) / 2;
    coarse.values.assign(static_cast<std::size_t>(coarse.width * coarse.height), 0.0f);
    coarse.fixed.assign(coarse.values.size(), 0);
    for (std::int64_t y = 0; y < coarse.height; ++y) {
        for (std::int64_t x = 0; x < coarse.width; ++x) {
            double sum = 0.0;
            int count = 0;
            for (std::int64_t dy = 0; dy < 2; ++dy)
                for (std::int64_t dx = 0; dx < 2; ++dx) {
                    const std::int64_t fx = 2 * x + dx, fy = 2 * y + dy;
                    if (fx >= fine.width || fy >= fine.height) continue;
                    const std::size_t i = fine.index(fx, fy);
                    if (!fine.fixed[i]) continue;
                    sum += fine.values[i];
                    ++count;
                }
            if (count == 0) continue;
            coarse.values[coarse.index(x, y)] = static_cast<float>(sum / count);
            coarse.fixed[coarse.index(x, y)] = 1;
        }
    }
    return coarse;
}

// The free fine cells start from the coarse solution, bilinear between coarse cell centres.
void prolong(const Grid& coarse, Grid& fine) {
    for (std::int64_t y = 0; y < fine.height; ++y) {
        const double cy = std::clamp((double(y) + 0.5) / 2.0 - 0.5, 0.0, double(coarse.height - 1));
        const auto y0 = static_cast<std::int64_t>(cy);
        const std::int64_t y1 = std::min(y0 + 1, coarse.height - 1);
        const double v = cy - double(y0);
        for (std::int64_t x = 0; x < fine.width; ++x) {
            const std::size_t i = fine.index(x, y);
            if (fine.fixed[i]) continue;
            const double cx =
                std::clamp((double(x) + 0.5) / 2.0 - 0.5, 0.0, double(coarse.width - 1));
            const auto x0 = static_cast<std::int64_t>(cx);
            const std::int64_t x1 = std::min(x0 + 1, coarse.width - 1);
            const double u = cx - double(x0);
            const double top = (1.0 - u) * coarse.values[coarse.index(x0, y0)] +
                               u * coarse.values[coarse.index(x1, y0)];
            const double bottom = (1.0 - u) * coarse.values[coarse.index(x0, y1)] +
                                  u * coarse.values[coarse.index(x1, y1)];
            fine.values[i] = static_cast<float>((1.0 - v) * top + v * bottom);
        }
    }
}

// Sweeps a level may take: the coarsest is solved to the tolerance, the finer ones start
// close to their solution.
constexpr int kCoarsestSweeps = 4000;
constexpr int kLevelSweeps = 1000;
constexpr std::int64_t kCoarsestCells = 64;

void solve(Grid& g) {
    if (g.width * g.height <= kCoarsestCells) {
        double sum = 0.0;
        int count = 0;
        for (std::size_t i = 0; i < g.values.size(); ++i)
            if (g.fixed[i]) sum += g.values[i], ++count;
        const float mean = count > 0 ? static_cast<float>(sum / count) : 0.0f;
        for (std::size_t i = 0; i < g.values.size(); ++i)
            if (!g.fixed[i]) g.values[i] = mean;
        if (count > 0) relax(g, kCoarsestSweeps);
        return;
    }
    {
        Grid coarse = coarsened(g);
        solve(coarse);
        prolong(coarse, g);
    }
    relax(g, kLevelSweeps);
}

}  // namespace

void fillMembrane(std::int64_t width, std::int64_t height, std::span<float> values,
                  std::span<const std::uint8_t> fixed) {
    TERRAIN_ASSERT(width > 0 && height > 0);
    TERRAIN_ASSERT(values.size() == static_cast<std::size_t>(width * height));
    TERRAIN_ASSERT(fixed.size() == values.size());
    Grid g{width, height, std::vector<float>(values.begin(), values.end()),
           std::vector<std::uint8_t>(fixed.begin(), fixed.end())};
    solve(g);
    std::copy(g.values.begin(), g.values.end(), values.begin());
}

}  // namespace terrain::io::detail
