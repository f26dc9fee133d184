// Error bounds of the patch quadtree: Yusov & Shevtsov 2011, §4 (Err_Int, nested like
// ROAM's wedgies) and §5 (tessellation-block errors λ(d)).
#include "terrain/pyramid/PatchErrors.h"

#include "StripChecks.h"

#include <half.h>

#include "terrain/base/Assert.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
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

// Four doubles, operated on lane by lane with IEEE arithmetic: each lane computes what the
// scalar code would, to the bit (GCC's and Clang's vector extensions: SSE2 pairs on the
// x86-64 baseline, AVX2 where the clone below runs). The helpers are always inlined, so
// the ABI GCC and Clang warn of for 32-byte vectors passed by value never applies.
#if defined(__GNUC__)  // GCC and Clang
#pragma GCC diagnostic ignored "-Wpsabi"
#endif
constexpr std::size_t kLanes = 4;
using Lanes = double __attribute__((vector_size(kLanes * sizeof(double))));
[[gnu::always_inline]] inline Lanes lanesAt(const double* p) {
    Lanes v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
[[gnu::always_inline]] inline Lanes splat(double x) { return Lanes{x, x, x, x}; }
// std::max and std::min, lane by lane (the same comparisons, so the same NaN and zero rules).
[[gnu::always_inline]] inline Lanes largerOf(Lanes a, Lanes b) { return a < b ? b : a; }
[[gnu::always_inline]] inline Lanes smallerOf(Lanes a, Lanes b) { return b < a ? b : a; }

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
        // Whole vectors of lanes: the points beyond weigh nothing (and their fine surface
        // is set to 0), so they deviate by 0 and leave the largest as it was.
        while (adA.size() % kLanes != 0) {
            push(adA, adB, adC, adD, 0.0, 0.0, 0.0, 0.0);
            push(bcA, bcB, bcC, bcD, 0.0, 0.0, 0.0, 0.0);
        }
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
[[gnu::always_inline]] inline double coarseCellDeviation(const GridView& g, int cx, int cy,
                                                         int step, const CellWeights& w,
                                                         std::vector<double>& fineLow,
                                                         std::vector<double>& fineHigh) {
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
    for (; p < w.adA.size(); ++p) fineLow[p] = fineHigh[p] = 0.0;  // the padding
    // A running maximum from +0 that passes over NaN (std::max(worst, NaN) is worst) ends
    // the same in any order, so four of them give the scalar loop's result to the bit.
    const Lanes a = splat(k.a), b = splat(k.b), c = splat(k.c), d = splat(k.d);
    Lanes worst = splat(0.0);
    for (std::size_t i = 0; i < p; i += kLanes) {
        const Lanes ad = lanesAt(&w.adA[i]) * a + lanesAt(&w.adB[i]) * b + lanesAt(&w.adC[i]) * c +
                         lanesAt(&w.adD[i]) * d;
        const Lanes bc = lanesAt(&w.bcA[i]) * a + lanesAt(&w.bcB[i]) * b + lanesAt(&w.bcC[i]) * c +
                         lanesAt(&w.bcD[i]) * d;
        const Lanes hi = largerOf(ad, bc), lo = smallerOf(ad, bc);
        worst = largerOf(worst, largerOf(hi - lanesAt(&fineLow[i]), lanesAt(&fineHigh[i]) - lo));
    }
    return std::max(std::max(worst[0], worst[1]), std::max(worst[2], worst[3]));
}

}  // namespace

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

BlockErrors transitionErrors(const GridView& patch, int x0, int y0, int blockQuads) {
    TERRAIN_ASSERT(blockQuads >= 1);
    TERRAIN_ASSERT(x0 >= 0 && y0 >= 0 && x0 + blockQuads <= patch.side - 1 &&
                   y0 + blockQuads <= patch.side - 1);
    // Which triangles a strip may hold and where each is checked depend on the block size
    // alone: worked out once (StripChecks.h).
    return detail::StripChecks::forBlock(blockQuads).errors(patch, x0, y0);
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

namespace {
// Compiled twice, for AVX2 and for the x86-64 baseline, the CPU's choosing which runs when
// the program loads (GCC's function multiversioning). Either computes the same IEEE
// operations (AVX2 brings no FMA to contract them into), so both give the same bits.
// Not under ThreadSanitizer: the load-time resolver that picks the clone would run
// instrumented before TSan's runtime is up, and every program would crash at its start.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_THREAD__)
__attribute__((target_clones("avx2", "default")))
#endif
double
worstCellDeviation(const GridView& grid, int x0, int y0, int quadsX, int quadsY, int step,
                   const CellWeights& weights, std::vector<double>& fineLow,
                   std::vector<double>& fineHigh) {
    double worst = 0.0;
    for (int cy = y0; cy < y0 + quadsY; cy += step)
        for (int cx = x0; cx < x0 + quadsX; cx += step)
            worst = std::max(worst,
                             coarseCellDeviation(grid, cx, cy, step, weights, fineLow, fineHigh));
    return worst;
}
}  // namespace

float simplificationError(const GridView& grid, int x0, int y0, int quadsX, int quadsY, int step) {
    TERRAIN_ASSERT(step >= 1 && quadsX % step == 0 && quadsY % step == 0,
                   "region must be whole coarse cells");
    TERRAIN_ASSERT(x0 >= 0 && y0 >= 0 && x0 + quadsX <= grid.side - 1 &&
                   y0 + quadsY <= grid.side - 1);
    if (step == 1) return 0.0f;
    std::optional<CellWeights> uncached;
    const CellWeights& weights = weightsFor(step, uncached);
    thread_local std::vector<double> fineLow, fineHigh;
    const std::size_t points = weights.adA.size();
    if (fineLow.size() < points) {
        fineLow.resize(points);
        fineHigh.resize(points);
    }
    return roundUpToFloat(
        worstCellDeviation(grid, x0, y0, quadsX, quadsY, step, weights, fineLow, fineHigh));
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
