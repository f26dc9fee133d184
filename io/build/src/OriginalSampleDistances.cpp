#include "OriginalSampleDistances.h"

#include "terrain/pyramid/PatchErrors.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace terrain::io::detail {
namespace {

// Source columns whose samples in stored row `row` lie in raster rows [yLow, yHigh], a
// sample's margin wider (the interval's ends are rounded outwards); empty if none.
struct ColumnSpan {
    std::int64_t first = 0, last = -1;
};

ColumnSpan columnsReaching(const ResampledGrid& grid, std::int64_t row, double yLow, double yHigh) {
    const std::array<double, 6>& a = grid.toGrid;
    const double base = a[3] + a[5] * double(row);  // raster y of column 0
    const std::int64_t lastColumn = grid.width - 1;
    if (a[4] == 0.0) {
        if (base < yLow - 1.0 || base > yHigh + 1.0) return {};
        return {0, lastColumn};
    }
    double c0 = (yLow - 1.0 - base) / a[4], c1 = (yHigh + 1.0 - base) / a[4];
    if (c0 > c1) std::swap(c0, c1);
    const double first = std::max(std::floor(c0), 0.0),
                 last = std::min(std::ceil(c1), double(lastColumn));
    if (first > last) return {};
    return {static_cast<std::int64_t>(first), static_cast<std::int64_t>(last)};
}

}  // namespace

double distanceToPatchSurface(const PatchRecord& patch, int tileSamples, int quads, double u,
                              double v, double height) {
    const auto cx = static_cast<int>(std::min(std::floor(u), double(quads - 1)));
    const auto cy = static_cast<int>(std::min(std::floor(v), double(quads - 1)));
    const int t = tileSamples;
    const float* h = patch.heights.data() + (cy + 1) * t + cx + 1;
    const auto [one, other] = cellSurfaceHeights(h[0], h[1], h[t], h[t + 1], u - cx, v - cy);
    return std::max(std::abs(one - height), std::abs(other - height));
}

Status visitOriginalSamples(
    DemReader& original, const ResampledGrid& grid, const PyramidLayout& layout, int level,
    std::int64_t firstPatchRow, std::int64_t patchRows,
    const std::function<const PatchRecord&(std::int64_t px, std::int64_t py)>& patchAt,
    const std::function<void(const PatchRecord& patch, std::int64_t column, std::int64_t row,
                             double distance)>& visit) {
    const std::int64_t s = layout.levelStep(level), q = layout.patchQuads();
    const std::int64_t span = q * s;  // raster samples per patch
    const std::int64_t patchesX = layout.patchesX(level), patchesY = layout.patchesY(level);
    const std::int64_t lastPatchRow = firstPatchRow + patchRows - 1;
    const int t = layout.tileSamples();
    const double maxX = double(layout.rasterWidth() - 1), maxY = double(layout.rasterHeight() - 1);
    // The raster rows of the patch rows; the last patch row holds the raster's last row.
    const double yLow = double(firstPatchRow * span);
    const double yHigh = lastPatchRow == patchesY - 1 ? maxY : double((lastPatchRow + 1) * span);
    const std::array<double, 6>& a = grid.toGrid;

    constexpr std::int64_t kRowsPerRead = 32;
    std::vector<ColumnSpan> spans;
    std::vector<float> samples;
    for (std::int64_t r0 = 0; r0 < grid.height; r0 += kRowsPerRead) {
        const std::int64_t rows = std::min(kRowsPerRead, grid.height - r0);
        spans.clear();
        std::int64_t first = std::numeric_limits<std::int64_t>::max(), last = -1;
        for (std::int64_t r = r0; r < r0 + rows; ++r) {
            spans.push_back(columnsReaching(grid, r, yLow, yHigh));
            if (spans.back().first <= spans.back().last) {
                first = std::min(first, spans.back().first);
                last = std::max(last, spans.back().last);
            }
        }
        if (last < first) continue;
        const std::int64_t width = last - first + 1;
        samples.resize(static_cast<std::size_t>(width * rows));
        if (Status read = original.readWindow(first, r0, width, rows, samples); !read) return read;
        for (std::int64_t r = r0; r < r0 + rows; ++r) {
            const ColumnSpan& columns = spans[static_cast<std::size_t>(r - r0)];
            const float* row = samples.data() + (r - r0) * width - first;
            for (std::int64_t c = columns.first; c <= columns.last; ++c) {
                if (std::isnan(row[c])) continue;
                // On the raster (inside it by construction; clamped against rounding).
                const double x = std::clamp(a[0] + a[1] * double(c) + a[2] * double(r), 0.0, maxX);
                const double y = std::clamp(a[3] + a[4] * double(c) + a[5] * double(r), 0.0, maxY);
                const std::int64_t py =
                    std::min(static_cast<std::int64_t>(std::floor(y / double(span))), patchesY - 1);
                if (py < firstPatchRow || py > lastPatchRow) continue;
                const std::int64_t px =
                    std::min(static_cast<std::int64_t>(std::floor(x / double(span))), patchesX - 1);
                const PatchRecord& patch = patchAt(px, py);
                const double u = (x - double(px * span)) / double(s);
                const double v = (y - double(py * span)) / double(s);
                visit(patch, c, r,
                      distanceToPatchSurface(patch, t, static_cast<int>(q), u, v, row[c]));
            }
        }
    }
    return {};
}

}  // namespace terrain::io::detail
