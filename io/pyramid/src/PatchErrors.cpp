// Error bounds of the patch quadtree: Yusov & Shevtsov 2011, §4 (Err_Int, nested like
// ROAM's wedgies) and §5 (tessellation-block errors λ(d)).
#include "terrain/pyramid/PatchErrors.h"

#include "RowSpan.h"

#include <half.h>

#include "terrain/base/Assert.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

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

Cell cellAt(const GridView& g, int x, int y, int side) {
    return {g.at(x, y), g.at(x + side, y), g.at(x, y + side), g.at(x + side, y + side)};
}

// Barycentric weights of the corners (a, b, c, d) at the points of a coarse cell of side
// `step` on both diagonals: at its (step + 1)² samples, then at its step² fine cell
// centres. Stored as separate arrays so the loops below run branch-free and vectorise;
// this is the build's hottest loop (every sample, four simplifications).
struct CellWeights {
    std::vector<double> adA, adB, adC, adD;  // diagonal a–d
    std::vector<double> bcA, bcB, bcC, bcD;  // diagonal b–c

    explicit CellWeights(int step) {
        const auto points = static_cast<std::size_t>((step + 1) * (step + 1) + step * step);
        for (auto* w : {&adA, &adB, &adC, &adD, &bcA, &bcB, &bcC, &bcD}) w->reserve(points);
        for (int j = 0; j <= step; ++j)
            for (int i = 0; i <= step; ++i) add(double(i) / step, double(j) / step);
        for (int j = 0; j < step; ++j)
            for (int i = 0; i < step; ++i) add((i + 0.5) / step, (j + 0.5) / step);
    }

    // The same triangles as cellHeights().
    void add(double u, double v) {
        if (u >= v)
            push(adA, adB, adC, adD, 1.0 - u, u - v, 0.0, v);
        else
            push(adA, adB, adC, adD, 1.0 - v, 0.0, v - u, u);
        if (u + v <= 1.0)
            push(bcA, bcB, bcC, bcD, 1.0 - u - v, u, v, 0.0);
        else
            push(bcA, bcB, bcC, bcD, 0.0, 1.0 - v, 1.0 - u, u + v - 1.0);
    }
    static void push(std::vector<double>& a, std::vector<double>& b, std::vector<double>& c,
                     std::vector<double>& d, double wa, double wb, double wc, double wd) {
        a.push_back(wa);
        b.push_back(wb);
        c.push_back(wc);
        d.push_back(wd);
    }
};

// Weights for power-of-two steps up to kCachedSteps are built once; others on demand.
constexpr int kCachedStepLog2 = 6;
const CellWeights& weightsFor(int step, std::optional<CellWeights>& uncached) {
    static const std::vector<CellWeights> cached = [] {
        std::vector<CellWeights> all;
        for (int k = 0; k <= kCachedStepLog2; ++k) all.emplace_back(1 << k);
        return all;
    }();
    const int log2 = std::countr_zero(static_cast<unsigned>(step));
    if ((1 << log2) == step && log2 <= kCachedStepLog2)
        return cached[static_cast<std::size_t>(log2)];
    uncached.emplace(step);
    return *uncached;
}

// Deviation of one coarse cell (side `step`, top-left (cx, cy)) from the full-resolution
// surface under it: at every sample, and at every fine cell centre (where the fine surface
// is the mean of one of its cell's diagonals).
double coarseCellDeviation(const GridView& g, int cx, int cy, int step, const CellWeights& w,
                           std::vector<double>& fineLow, std::vector<double>& fineHigh) {
    const Cell k = cellAt(g, cx, cy, step);
    // The fine surface at each point, as an interval [low, high] (one value at samples).
    std::size_t p = 0;
    for (int j = 0; j <= step; ++j)
        for (int i = 0; i <= step; ++i, ++p) fineLow[p] = fineHigh[p] = g.at(cx + i, cy + j);
    for (int j = 0; j < step; ++j) {
        for (int i = 0; i < step; ++i, ++p) {
            const Cell f = cellAt(g, cx + i, cy + j, 1);
            const double alongAD = 0.5 * (f.a + f.d), alongBC = 0.5 * (f.b + f.c);
            fineLow[p] = std::min(alongAD, alongBC);
            fineHigh[p] = std::max(alongAD, alongBC);
        }
    }
    double worst = 0.0;
    const std::size_t points = p;
    for (std::size_t i = 0; i < points; ++i) {
        const double ad = w.adA[i] * k.a + w.adB[i] * k.b + w.adC[i] * k.c + w.adD[i] * k.d;
        const double bc = w.bcA[i] * k.a + w.bcB[i] * k.b + w.bcC[i] * k.c + w.bcD[i] * k.d;
        const double hi = std::max(ad, bc), lo = std::min(ad, bc);
        worst = std::max(worst, std::max(hi - fineLow[i], fineHigh[i] - lo));
    }
    return worst;
}

// ---- Transition strips -------------------------------------------------------------------
//
// Where a block edge's factor m exceeds the block's inner factor n, GL's tessellator fills
// the strip between the edge and the inner mesh with triangles that join the edge's m + 1
// vertices to the n − 1 vertices of the inner mesh's side (GL 4.5 §11.2.2.2; an inner
// factor of 1 becomes 2 when any edge is finer, and the inner side is the block's centre).
// Which vertices it joins GL leaves to the implementation: a triangle has two consecutive
// vertices on one side and one on the other. Implementations stitch the two sides in
// step (D3D11's reference tessellator, which Mesa uses, and the hardware that follows it),
// so the lone vertex lies within one inner spacing of the pair's span: llvmpipe's strips
// reach 0.875 of it, and TransitionStripTest checks every strip the fine LOD can ask for
// on the driver the tests run on. All such triangles count here, whichever the driver
// picks. They are not the regular triangulation that λ(d) measures, so their error is
// added to it.

struct SamplePoint {
    int x, y;
};

double heightAt(const GridView& g, SamplePoint p) { return g.at(p.x, p.y); }

// The full-resolution surface at a point of the vertical line x = X (y not a sample row in
// general): grid lines are edges of every fine triangulation, so one value.
double surfaceOnColumn(const GridView& g, int X, double y) {
    const int cy = std::min(static_cast<int>(std::floor(y)), g.side - 2);
    const double h0 = g.at(X, cy);
    return h0 + (y - cy) * (g.at(X, cy + 1) - h0);
}

double surfaceOnRow(const GridView& g, double x, int Y) {
    const int cx = std::min(static_cast<int>(std::floor(x)), g.side - 2);
    const double h0 = g.at(cx, Y);
    return h0 + (x - cx) * (g.at(cx + 1, Y) - h0);
}

// Largest |f − L| along the segment p → q, where L interpolates the heights at p and q
// linearly and f is the full-resolution surface under either diagonal of every cell. Both
// are linear between the points where the segment crosses a grid line or a cell diagonal,
// so those points (for both diagonals) are the only ones to check.
double segmentDeviation(const GridView& g, SamplePoint p, SamplePoint q) {
    const double hp = heightAt(g, p), hq = heightAt(g, q);
    const int dx = q.x - p.x, dy = q.y - p.y;
    double worst = 0.0;
    if (dx == 0 || dy == 0) {
        // Along a grid line, an edge of every fine triangulation: f is linear between the
        // samples, and every diagonal crosses it at one. The samples are the only points.
        const int steps = std::abs(dx) + std::abs(dy);
        const int sx = (dx > 0) - (dx < 0), sy = (dy > 0) - (dy < 0);
        for (int k = 1; k < steps; ++k) {
            const double s = double(k) / steps;
            worst =
                std::max(worst, std::abs(g.at(p.x + k * sx, p.y + k * sy) - (hp + s * (hq - hp))));
        }
        return worst;
    }
    auto check = [&](double s, double surface) {
        worst = std::max(worst, std::abs(surface - (hp + s * (hq - hp))));
    };
    // Crossings of the lines where a coordinate function c(point) = c(p) + s·dc is an
    // integer, for dc ≠ 0.
    auto crossings = [&](int c0, int dc, auto&& surfaceAt) {
        if (dc == 0) return;
        const int step = dc > 0 ? 1 : -1;
        for (int k = c0; k != c0 + dc + step; k += step) {
            const double s = double(k - c0) / dc;
            surfaceAt(k, s, p.x + s * dx, p.y + s * dy);
        }
    };
    crossings(p.x, dx,
              [&](int X, double s, double, double y) { check(s, surfaceOnColumn(g, X, y)); });
    crossings(p.y, dy, [&](int Y, double s, double x, double) { check(s, surfaceOnRow(g, x, Y)); });
    // Diagonal a–d of cell (cx, cy) runs from (cx, cy) to (cx + 1, cy + 1): x − y = cx − cy.
    crossings(p.x - p.y, dx - dy, [&](int k, double s, double x, double) {
        const int cx = std::min(static_cast<int>(std::floor(x)), g.side - 2), cy = cx - k;
        if (cy < 0 || cy > g.side - 2) return;  // a grid corner: checked as a sample
        const double t = x - cx, h0 = g.at(cx, cy);
        check(s, h0 + t * (g.at(cx + 1, cy + 1) - h0));
    });
    // Diagonal b–c of cell (cx, cy) runs from (cx, cy + 1) to (cx + 1, cy): x + y = cx + cy + 1.
    crossings(p.x + p.y, dx + dy, [&](int k, double s, double x, double) {
        const int cx = std::min(static_cast<int>(std::floor(x)), g.side - 2), cy = k - cx - 1;
        if (cy < 0 || cy > g.side - 2) return;
        const double t = x - cx, h0 = g.at(cx, cy + 1);
        check(s, h0 + t * (g.at(cx + 1, cy) - h0));
    });
    return worst;
}

// Largest |f − L| at the samples inside the triangle abc (its boundary included), where L
// is the plane through the heights at its corners.
double interiorDeviation(const GridView& g, SamplePoint a, SamplePoint b, SamplePoint c) {
    const double area2 = double(b.x - a.x) * (c.y - a.y) - double(c.x - a.x) * (b.y - a.y);
    if (area2 == 0.0) return 0.0;
    const double ha = heightAt(g, a), hb = heightAt(g, b), hc = heightAt(g, c);
    // L = ha + gx·(x − a.x) + gy·(y − a.y): one multiply-add a sample (the build's hottest
    // loop with segmentDeviation).
    const double gx = ((hb - ha) * (c.y - a.y) - (hc - ha) * (b.y - a.y)) / area2;
    const double gy = ((hc - ha) * (b.x - a.x) - (hb - ha) * (c.x - a.x)) / area2;
    const int yLo = std::min({a.y, b.y, c.y}), yHi = std::max({a.y, b.y, c.y});
    double worst = 0.0;
    for (int y = yLo; y <= yHi; ++y) {
        // The samples of row y inside the triangle: from the first at or right of its edges'
        // leftmost crossing of the row to the last at or left of the rightmost, in integers
        // (RowSpan.h: the same samples as the crossings in floating point, without their
        // divisions on the loop's path).
        const RowSpan span = triangleRowSpan({a.x, a.y}, {b.x, b.y}, {c.x, c.y}, y);
        const double rowPlane = ha + gy * (y - a.y);
        const float* row = g.data + static_cast<std::ptrdiff_t>(y) * g.stride;
        for (int x = span.first; x <= span.last; ++x)
            worst = std::max(worst, std::abs(row[x] - (rowPlane + gx * (x - a.x))));
    }
    return worst;
}

// The largest deviation of the strip triangles of a block with inner factor `inner`
// (≥ 2, a power of two) against edges of every power-of-two factor m from 1 (inner 2) or
// 2·inner up to blockQuads, over the block's four edges: out[log2 m].
template <std::size_t kFactors>
void stripDeviations(const GridView& patch, int x0, int y0, int blockQuads, int inner,
                     std::array<double, kFactors>& out) {
    const int innerSpacing = blockQuads / inner;
    const int innerCount = inner - 1;  // vertices of the inner mesh's side, j = 1..inner−1
    // Whether a strip may join a lone vertex at `along` to a pair spanning [from, to].
    auto withinReach = [&](int along, int from, int to) {
        return along >= from - innerSpacing && along <= to + innerSpacing;
    };
    thread_local std::vector<double> toEdge, innerSide;
    for (int edge = 0; edge < 4; ++edge) {
        // Edge `edge`'s frame: `along` runs along the edge, `inward` into the block.
        auto at = [&](int along, int inward) -> SamplePoint {
            switch (edge) {
                case 0:
                    return {x0 + along, y0 + inward};
                case 1:
                    return {x0 + along, y0 + blockQuads - inward};
                case 2:
                    return {x0 + inward, y0 + along};
                default:
                    return {x0 + blockQuads - inward, y0 + along};
            }
        };
        auto innerVertex = [&](int j) { return at(j * innerSpacing, innerSpacing); };
        // Segments from edge samples to inner vertices, computed once each.
        toEdge.assign(static_cast<std::size_t>((blockQuads + 1) * innerCount), -1.0);
        auto toEdgeDeviation = [&](int along, int j) {
            double& cached = toEdge[static_cast<std::size_t>(along * innerCount + j - 1)];
            if (cached < 0.0) cached = segmentDeviation(patch, at(along, 0), innerVertex(j));
            return cached;
        };
        innerSide.assign(static_cast<std::size_t>(std::max(0, innerCount - 1)), 0.0);
        for (int j = 1; j < innerCount; ++j)
            innerSide[static_cast<std::size_t>(j - 1)] =
                segmentDeviation(patch, innerVertex(j), innerVertex(j + 1));

        const int firstEdgeFactor = inner == 2 ? 1 : 2 * inner;
        for (int edgeFactor = firstEdgeFactor; edgeFactor <= blockQuads; edgeFactor *= 2) {
            const int edgeSpacing = blockQuads / edgeFactor;
            double worst = 0.0;
            // Two consecutive edge vertices and an inner vertex.
            for (int k = 0; k < edgeFactor; ++k) {
                const int from = k * edgeSpacing, to = from + edgeSpacing;
                const double alongEdge = segmentDeviation(patch, at(from, 0), at(to, 0));
                for (int j = 1; j <= innerCount; ++j) {
                    if (!withinReach(j * innerSpacing, from, to)) continue;
                    worst = std::max(
                        {worst, alongEdge, toEdgeDeviation(from, j), toEdgeDeviation(to, j),
                         interiorDeviation(patch, at(from, 0), at(to, 0), innerVertex(j))});
                }
            }
            // Two consecutive inner vertices and an edge vertex.
            for (int j = 1; j < innerCount; ++j) {
                for (int k = 0; k <= edgeFactor; ++k) {
                    const int along = k * edgeSpacing;
                    if (!withinReach(along, j * innerSpacing, (j + 1) * innerSpacing)) continue;
                    worst = std::max({worst, innerSide[static_cast<std::size_t>(j - 1)],
                                      toEdgeDeviation(along, j), toEdgeDeviation(along, j + 1),
                                      interiorDeviation(patch, innerVertex(j), innerVertex(j + 1),
                                                        at(along, 0))});
                }
            }
            double& slot =
                out[static_cast<std::size_t>(std::countr_zero(static_cast<unsigned>(edgeFactor)))];
            slot = std::max(slot, worst);
        }
    }
}

}  // namespace

BlockErrors transitionErrors(const GridView& patch, int x0, int y0, int blockQuads) {
    TERRAIN_ASSERT(blockQuads >= 1);
    TERRAIN_ASSERT(x0 >= 0 && y0 >= 0 && x0 + blockQuads <= patch.side - 1 &&
                   y0 + blockQuads <= patch.side - 1);
    // strips[log2 inner][log2 m]: the largest deviation of the strips between edges of
    // factor m and an inner mesh of factor `inner` (≥ 2), filled where some d needs it.
    constexpr int kFactors = 17;  // log2 of factors up to 2^16, far beyond GL's 64
    std::array<std::array<double, kFactors>, kFactors> strips{};
    std::array<bool, kFactors> stripsDone{};
    BlockErrors errors{};
    for (int d = 1; d <= kMaxSimplification; ++d) {
        const int innerFactor = std::max(1, blockQuads >> d);
        // An inner factor of 1 becomes 2 once an edge is finer (GL 4.5 §11.2.2.2); then an
        // edge of factor 1 joins the centre too.
        const int inner = std::max(2, innerFactor);
        const int firstEdgeFactor = innerFactor == 1 ? 1 : 2 * innerFactor;
        if (blockQuads < 2 || firstEdgeFactor > blockQuads) continue;
        const int innerLog2 = std::countr_zero(static_cast<unsigned>(inner));
        TERRAIN_ASSERT(innerLog2 < kFactors);
        if (!stripsDone[static_cast<std::size_t>(innerLog2)]) {
            // For inner 2 these start at edge factor 1: inner factors 1 and 2 both make the
            // centre fan, so they share them.
            stripDeviations(patch, x0, y0, blockQuads, inner,
                            strips[static_cast<std::size_t>(innerLog2)]);
            stripsDone[static_cast<std::size_t>(innerLog2)] = true;
        }
        double worst = 0.0;
        for (int m = firstEdgeFactor; m <= blockQuads; m *= 2)
            worst = std::max(worst,
                             strips[static_cast<std::size_t>(innerLog2)][static_cast<std::size_t>(
                                 std::countr_zero(static_cast<unsigned>(m)))]);
        errors[static_cast<std::size_t>(d - 1)] = roundUpToFloat(worst);
    }
    return errors;
}

std::pair<double, double> cellSurfaceHeights(double a, double b, double c, double d, double u,
                                             double v) {
    const TwoHeights h = cellHeights(Cell{a, b, c, d}, u, v);
    return {h.first, h.second};
}

float roundUpToHalf(float bound) {
    const Imath::half nearest(bound);  // round to nearest: may be below
    if (static_cast<float>(nearest) >= bound) return static_cast<float>(nearest);
    Imath::half up;
    up.setBits(static_cast<unsigned short>(nearest.bits() + 1U));  // the next half up (≥ 0)
    return static_cast<float>(up);
}

float roundUpToFloat(double value) {
    auto f = static_cast<float>(value);
    if (static_cast<double>(f) < value)
        f = std::nextafter(f, std::numeric_limits<float>::infinity());
    return f;
}

float simplificationError(const GridView& grid, int x0, int y0, int quadsX, int quadsY, int step) {
    TERRAIN_ASSERT(step >= 1 && quadsX % step == 0 && quadsY % step == 0,
                   "region must be whole coarse cells");
    TERRAIN_ASSERT(x0 >= 0 && y0 >= 0 && x0 + quadsX <= grid.side - 1 &&
                   y0 + quadsY <= grid.side - 1);
    if (step == 1) return 0.0f;
    std::optional<CellWeights> uncached;
    const CellWeights& weights = weightsFor(step, uncached);
    thread_local std::vector<double> fineLow, fineHigh;
    const auto points = static_cast<std::size_t>((step + 1) * (step + 1) + step * step);
    if (fineLow.size() < points) {
        fineLow.resize(points);
        fineHigh.resize(points);
    }
    double worst = 0.0;
    for (int cy = y0; cy < y0 + quadsY; cy += step)
        for (int cx = x0; cx < x0 + quadsX; cx += step)
            worst = std::max(worst,
                             coarseCellDeviation(grid, cx, cy, step, weights, fineLow, fineHigh));
    return roundUpToFloat(worst);
}

float simplificationError(const GridView& grid, int x0, int y0, int quads, int step) {
    return simplificationError(grid, x0, y0, quads, quads, step);
}

float interpolationError(const GridView& children) {
    TERRAIN_ASSERT(children.side >= 3 && (children.side - 1) % 2 == 0);
    return simplificationError(children, 0, 0, children.side - 1, 2);
}

BlockErrors blockErrors(const GridView& patch, int x0, int y0, int blockQuads) {
    const BlockErrors transitions = transitionErrors(patch, x0, y0, blockQuads);
    BlockErrors errors{};
    // Once 2^d reaches the block's side the step stops growing (the whole block is one
    // cell): the same simplification error, measured once.
    int measuredStep = 0;
    float simplification = 0.0f;
    for (int d = 1; d <= kMaxSimplification; ++d) {
        const int step = std::min(1 << d, blockQuads);
        if (step != measuredStep) {
            simplification = simplificationError(patch, x0, y0, blockQuads, step);
            measuredStep = step;
        }
        errors[d - 1] = std::max(simplification, transitions[static_cast<std::size_t>(d - 1)]);
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
