// Error bounds of the patch quadtree: Yusov & Shevtsov 2011, §4 (Err_Int, nested like
// ROAM's wedgies) and §5 (tessellation-block errors λ(d)).
#include "terrain/io/PatchErrors.h"

#include "terrain/io/Assert.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace terrain::io {
namespace {

// Heights of a cell's corners: a = top-left, b = top-right, c = bottom-left, d = bottom-right.
struct Cell {
    double a, b, c, d;
};

// The two heights the cell's surface can have at local (u, v) ∈ [0,1]², one per diagonal.
// Diagonal a–d: triangles (a,b,d) where u ≥ v and (a,c,d) where v > u.
// Diagonal b–c: triangles (a,b,c) where u + v ≤ 1 and (b,c,d) where u + v > 1.
struct TwoHeights {
    double first, second;
};

TwoHeights cellHeights(const Cell& k, double u, double v) {
    const double alongAD =
        u >= v ? k.a + (k.b - k.a) * u + (k.d - k.b) * v : k.a + (k.d - k.c) * u + (k.c - k.a) * v;
    const double alongBC = u + v <= 1.0 ? k.a + (k.b - k.a) * u + (k.c - k.a) * v
                                        : k.d + (k.c - k.d) * (1.0 - u) + (k.b - k.d) * (1.0 - v);
    return {alongAD, alongBC};
}

double largestGap(const TwoHeights& coarse, const TwoHeights& fine) {
    return std::max({std::abs(coarse.first - fine.first), std::abs(coarse.first - fine.second),
                     std::abs(coarse.second - fine.first), std::abs(coarse.second - fine.second)});
}

Cell cellAt(const GridView& g, int x, int y, int side) {
    return {g.at(x, y), g.at(x + side, y), g.at(x, y + side), g.at(x + side, y + side)};
}

float roundUpToFloat(double value) {
    auto f = static_cast<float>(value);
    if (static_cast<double>(f) < value)
        f = std::nextafter(f, std::numeric_limits<float>::infinity());
    return f;
}

// Deviation of one coarse cell (side `step`, top-left (cx, cy)) from the full-resolution
// surface under it: at every sample, and at every fine cell centre.
double coarseCellDeviation(const GridView& g, int cx, int cy, int step) {
    const Cell coarse = cellAt(g, cx, cy, step);
    const double inverseStep = 1.0 / step;
    double worst = 0.0;
    for (int j = 0; j <= step; ++j) {
        const double v = j * inverseStep;
        for (int i = 0; i <= step; ++i) {
            const double h = g.at(cx + i, cy + j);
            const TwoHeights s = cellHeights(coarse, i * inverseStep, v);
            worst = std::max({worst, std::abs(s.first - h), std::abs(s.second - h)});
        }
    }
    for (int j = 0; j < step; ++j) {
        const double v = (j + 0.5) * inverseStep;
        for (int i = 0; i < step; ++i) {
            const Cell fine = cellAt(g, cx + i, cy + j, 1);
            // The fine surface at its cell centre is the mean of one diagonal's ends.
            const TwoHeights f{0.5 * (fine.a + fine.d), 0.5 * (fine.b + fine.c)};
            worst = std::max(worst, largestGap(cellHeights(coarse, (i + 0.5) * inverseStep, v), f));
        }
    }
    return worst;
}

}  // namespace

float simplificationError(const GridView& grid, int x0, int y0, int quads, int step) {
    TERRAIN_ASSERT(step >= 1 && quads % step == 0, "region must be whole coarse cells");
    TERRAIN_ASSERT(x0 >= 0 && y0 >= 0 && x0 + quads <= grid.side - 1 &&
                   y0 + quads <= grid.side - 1);
    if (step == 1) return 0.0f;
    double worst = 0.0;
    for (int cy = y0; cy < y0 + quads; cy += step)
        for (int cx = x0; cx < x0 + quads; cx += step)
            worst = std::max(worst, coarseCellDeviation(grid, cx, cy, step));
    return roundUpToFloat(worst);
}

float interpolationError(const GridView& children) {
    TERRAIN_ASSERT(children.side >= 3 && (children.side - 1) % 2 == 0);
    return simplificationError(children, 0, 0, children.side - 1, 2);
}

BlockErrors blockErrors(const GridView& patch, int x0, int y0, int blockQuads) {
    BlockErrors errors{};
    for (int d = 1; d <= kMaxSimplification; ++d) {
        const int step = std::min(1 << d, blockQuads);
        errors[d - 1] = simplificationError(patch, x0, y0, blockQuads, step);
    }
    return errors;
}

void patchBlockErrors(const GridView& patch, int blockQuads, std::span<BlockErrors> out) {
    TERRAIN_ASSERT(blockQuads >= 1 && (patch.side - 1) % blockQuads == 0);
    const int blocksPerSide = (patch.side - 1) / blockQuads;
    TERRAIN_ASSERT(out.size() == static_cast<std::size_t>(blocksPerSide) * blocksPerSide);
    for (int by = 0; by < blocksPerSide; ++by)
        for (int bx = 0; bx < blocksPerSide; ++bx)
            out[static_cast<std::size_t>(by) * blocksPerSide + bx] =
                blockErrors(patch, bx * blockQuads, by * blockQuads, blockQuads);
}

}  // namespace terrain::io
