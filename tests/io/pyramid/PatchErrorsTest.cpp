// Yusov §4/§5 error bounds against a brute force that shares no code with them: every
// point of the half-sample lattice (which holds every vertex of the common refinement of
// a fine and a coarse triangulation) under every diagonal choice, by barycentric
// interpolation.
#include "terrain/pyramid/PatchErrors.h"

#include "terrain/pyramid/BlockHeightRanges.h"
#include "terrain/pyramid/CoarseCellErrors.h"

#include "TriangulationOracle.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

namespace terrain::io {
namespace {

// Every height the surface of cell (cx, cy, side s) can have at (x, y): one per diagonal.
std::vector<double> surfaceHeights(const std::vector<float>& h, int n, int cx, int cy, int s,
                                   double x, double y) {
    return test::cellSurfaceHeights([&](int i, int j) { return double(h[j * n + i]); }, cx, cy, s,
                                    x, y);
}

double bruteForce(const std::vector<float>& h, int n, int x0, int y0, int quads, int step) {
    double worst = 0.0;
    for (int j2 = 0; j2 <= 2 * quads; ++j2) {
        for (int i2 = 0; i2 <= 2 * quads; ++i2) {
            const double x = x0 + i2 * 0.5, y = y0 + j2 * 0.5;
            auto cellOf = [&](double p, int origin, int s) {
                return origin + std::min(int((p - origin) / s), quads / s - 1) * s;
            };
            const auto coarse =
                surfaceHeights(h, n, cellOf(x, x0, step), cellOf(y, y0, step), step, x, y);
            const auto fine = surfaceHeights(h, n, cellOf(x, x0, 1), cellOf(y, y0, 1), 1, x, y);
            for (double zc : coarse)
                for (double zf : fine) worst = std::max(worst, std::abs(zc - zf));
        }
    }
    return worst;
}

std::vector<float> randomGrid(int n, unsigned seed, float roughness) {
    std::mt19937 rng(seed);
    std::normal_distribution<float> noise(0.0f, roughness);
    std::vector<float> h(static_cast<std::size_t>(n) * n);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            h[y * n + x] =
                100.0f * std::sin(0.1f * float(x)) + 30.0f * float(y) / float(n) + noise(rng);
    return h;
}

TEST(PatchErrors, SimplificationErrorEqualsBruteForce) {
    const int n = 33, blockQuads = 16;
    for (unsigned seed = 1; seed <= 6; ++seed) {
        const auto h = randomGrid(n, seed, seed % 2 ? 5.0f : 0.0f);
        const GridView g{h.data(), n, n};
        for (int by = 0; by < 2; ++by) {
            for (int bx = 0; bx < 2; ++bx) {
                for (int d = 1; d <= kMaxSimplification; ++d) {
                    const int step = std::min(1 << d, blockQuads);
                    const float got =
                        simplificationError(g, bx * blockQuads, by * blockQuads, blockQuads, step);
                    const double want =
                        bruteForce(h, n, bx * blockQuads, by * blockQuads, blockQuads, step);
                    EXPECT_GE(double(got), want) << "seed " << seed << " d " << d;
                    EXPECT_NEAR(double(got), want, 1e-4 * (1.0 + want)) << "d " << d;
                }
            }
        }
    }
}

// The strip triangles of a block of `blockQuads` (top-left (x0, y0)) whose inner factor
// is that of simplification d, enumerated from GL 4.5 §11.2.2.2 as PatchErrors.h states
// the model: every finer power-of-two edge factor, two consecutive vertices of one side
// and a vertex of the other within one inner spacing.
std::vector<std::array<std::array<int, 2>, 3>> stripTriangles(int x0, int y0, int blockQuads,
                                                              int d) {
    const int innerFactor = std::max(1, blockQuads >> d);
    const int inner = std::max(2, innerFactor), spacing = blockQuads / inner;
    std::vector<std::array<std::array<int, 2>, 3>> triangles;
    for (int edge = 0; edge < 4; ++edge) {
        auto at = [&](int along, int inward) -> std::array<int, 2> {
            if (edge == 0) return {x0 + along, y0 + inward};
            if (edge == 1) return {x0 + along, y0 + blockQuads - inward};
            if (edge == 2) return {x0 + inward, y0 + along};
            return {x0 + blockQuads - inward, y0 + along};
        };
        for (int m = innerFactor == 1 ? 1 : 2 * innerFactor; m <= blockQuads; m *= 2) {
            const int step = blockQuads / m;
            for (int a = 0; a + step <= blockQuads; a += step)
                for (int j = 1; j < inner; ++j)
                    if (j * spacing >= a - spacing && j * spacing <= a + step + spacing)
                        triangles.push_back({at(a, 0), at(a + step, 0), at(j * spacing, spacing)});
            for (int j = 1; j + 1 < inner; ++j)
                for (int a = 0; a <= blockQuads; a += step)
                    if (a >= j * spacing - spacing && a <= (j + 1) * spacing + spacing)
                        triangles.push_back(
                            {at(j * spacing, spacing), at((j + 1) * spacing, spacing), at(a, 0)});
        }
    }
    return triangles;
}

// The strips' checks are worked out once per block size (StripChecks), with a form for
// blocks on the grid's last row or column (cells clamped there) and one for the rest
// (crossings on a sample merged): every form, at every kind of place, and a block
// of 64 quads (the largest a layout allows), against the oracle.
TEST(PatchErrors, TransitionErrorsEqualBruteForce) {
    struct Case {
        int n, blockQuads, x0, y0;
        unsigned seeds;
    };
    std::vector<Case> cases;
    for (int blockQuads : {16, 8, 4, 2}) {
        const int last = 32 - blockQuads;
        cases.push_back({33, blockQuads, 16 - blockQuads / 2, 8, 3});  // inside
        cases.push_back({33, blockQuads, 0, 0, 3});                    // at the origin
        cases.push_back({33, blockQuads, last, last, 3});              // on the last row and column
        cases.push_back({33, blockQuads, last, 8, 2});                 // on the last column
        cases.push_back({33, blockQuads, 8, last, 2});                 // on the last row
        cases.push_back({33, blockQuads, last, 0, 2});  // on the last column and the first row
        cases.push_back({blockQuads + 1, blockQuads, 0, 0, 2});  // the grid's only block
    }
    cases.push_back({65, 64, 0, 0, 1});  // the largest block, one set of checks of its own
    for (const auto [n, blockQuads, x0, y0, seeds] : cases) {
        for (unsigned seed = 1; seed <= seeds; ++seed) {
            const auto h = randomGrid(n, seed, seed % 2 ? 8.0f : 0.5f);
            const GridView g{h.data(), n, n};
            auto height = [&](int x, int y) { return double(h[y * n + x]); };
            SCOPED_TRACE(testing::Message() << "block " << blockQuads << " at " << x0 << "," << y0
                                            << " seed " << seed);
            const BlockErrors got = transitionErrors(g, x0, y0, blockQuads);
            for (int d = 1; d <= kMaxSimplification; ++d) {
                double want = 0.0;
                for (const auto& t : stripTriangles(x0, y0, blockQuads, d)) {
                    auto corner = [&](std::array<int, 2> p) {
                        return test::Point3{double(p[0]), double(p[1]), height(p[0], p[1])};
                    };
                    want = std::max(want, test::triangleSurfaceDeviation(
                                              height, corner(t[0]), corner(t[1]), corner(t[2])));
                }
                // The oracle's own rounding may put it a few ulps above.
                EXPECT_GE(double(got[d - 1]), want * (1.0 - 1e-12))
                    << "block " << blockQuads << " d " << d;
                EXPECT_NEAR(double(got[d - 1]), want, 1e-4 * (1.0 + want))
                    << "block " << blockQuads << " d " << d;
            }
        }
    }
}

TEST(PatchErrors, BlockErrorsCoverTheRegularSimplificationAndTheStrips) {
    const int n = 33, blockQuads = 16;
    const auto h = randomGrid(n, 7, 8.0f);
    const GridView g{h.data(), n, n};
    int stripsLarger = 0;
    for (int by = 0; by < 2; ++by) {
        for (int bx = 0; bx < 2; ++bx) {
            const int x0 = bx * blockQuads, y0 = by * blockQuads;
            const BlockErrors lambda = blockErrors(g, x0, y0, blockQuads);
            const BlockErrors strips = transitionErrors(g, x0, y0, blockQuads);
            for (int d = 1; d <= kMaxSimplification; ++d) {
                const float regular =
                    simplificationError(g, x0, y0, blockQuads, std::min(1 << d, blockQuads));
                EXPECT_EQ(lambda[d - 1], std::max(regular, strips[d - 1])) << "d " << d;
                stripsLarger += strips[d - 1] > regular;
            }
        }
    }
    // On rough ground the strips are what bounds some levels: Yusov's λ alone would not.
    EXPECT_GT(stripsLarger, 0);
}

TEST(PatchErrors, InterpolationErrorEqualsBruteForceAndBoundsEverySample) {
    const int n = 17;  // four 9×9 children joined: the parent is their even samples
    for (unsigned seed = 10; seed < 16; ++seed) {
        const auto h = randomGrid(n, seed, 20.0f);
        const float err = interpolationError(GridView{h.data(), n, n});
        EXPECT_NEAR(double(err), bruteForce(h, n, 0, 0, n - 1, 2), 1e-4 * (1.0 + err));
        // Every child sample lies within err of the parent surface, whatever the diagonals.
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x)
                for (double z : surfaceHeights(h, n, std::min(x / 2 * 2, n - 3),
                                               std::min(y / 2 * 2, n - 3), 2, x, y))
                    EXPECT_LE(std::abs(z - h[y * n + x]), double(err));
    }
}

TEST(PatchErrors, PlanesHaveNoError) {
    const int n = 33;
    std::vector<float> h(n * n);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) h[y * n + x] = 0.5f * float(x) - 0.25f * float(y) + 7.0f;
    std::vector<BlockErrors> blocks(4);
    patchBlockErrors(GridView{h.data(), n, n}, 16, blocks);
    // The strips' skewed triangles are interpolated with rational weights: a plane comes
    // out within double rounding of 0, far below anything on screen.
    for (const auto& b : blocks)
        for (float e : b) EXPECT_LE(e, 1e-12f);
    EXPECT_EQ(interpolationError(GridView{h.data(), n, n}), 0.0f);
}

TEST(PatchErrors, LevelGroundHasExactlyNoError) {
    // What lets a flat plain collapse to factor 1 everywhere (LodTriangleBudgetTest).
    const int n = 33;
    const std::vector<float> h(n * n, 12.5f);
    std::vector<BlockErrors> blocks(4);
    patchBlockErrors(GridView{h.data(), n, n}, 16, blocks);
    for (const auto& b : blocks)
        for (float e : b) EXPECT_EQ(e, 0.0f);
}

TEST(PatchErrors, SingleSpikeIsSeenByEveryCoarserLevel) {
    const int n = 17;
    std::vector<float> h(n * n, 10.0f);
    h[5 * n + 7] = 1010.0f;  // odd position: dropped at every simplification
    const BlockErrors e = blockErrors(GridView{h.data(), n, n}, 0, 0, 16);
    for (float v : e) EXPECT_FLOAT_EQ(v, 1000.0f);
}

// Coarse cells (CoarseCellErrors.h): a patch drawn as cells of 2^k × 2^k blocks, one quad
// each. The bound of every cell covers the brute-force distance between its two triangles
// (either diagonal) and the full-resolution surface under it.
TEST(PatchErrors, CoarseCellBoundsCoverTheirCellsBruteForceError) {
    EXPECT_EQ(coarseCellLevels(128, 8), 4);
    EXPECT_EQ(coarseCellCount(128, 8), 64 + 16 + 4 + 1);
    EXPECT_EQ(coarseCellCount(128, 4), 256 + 64 + 16 + 4 + 1);
    EXPECT_EQ(coarseCellCount(128, 16), 16 + 4 + 1);
    EXPECT_EQ(coarseCellLevels(128, 32), 0);  // λ has no factor-1 level for blocks of 32
    const int n = 65, blockQuads = 8, blocks = 8;
    ASSERT_EQ(coarseCellLevels(n - 1, blockQuads), 3);
    int looserThanTwice = 0, cells = 0;
    for (unsigned seed = 20; seed < 24; ++seed) {
        const auto h = randomGrid(n, seed, seed % 2 ? 6.0f : 0.5f);
        const GridView g{h.data(), n, n};
        std::vector<BlockErrors> lambda(blocks * blocks);
        patchBlockErrors(g, blockQuads, lambda);
        const std::vector<float> bounds = coarseCellErrors(g, blockQuads, lambda);
        ASSERT_EQ(bounds.size(), std::size_t(16 + 4 + 1));
        for (int k = 1; k <= 3; ++k) {
            const int cellQuads = blockQuads << k, perSide = blocks >> k;
            for (int cy = 0; cy < perSide; ++cy) {
                for (int cx = 0; cx < perSide; ++cx) {
                    const double exact =
                        bruteForce(h, n, cx * cellQuads, cy * cellQuads, cellQuads, cellQuads);
                    const double bound = bounds[coarseCellOffset(blocks, k) + cy * perSide + cx];
                    EXPECT_GE(bound + 1e-4 * (1.0 + bound), exact)
                        << "seed " << seed << ", cells of " << cellQuads << " quads, cell (" << cx
                        << ", " << cy << ")";
                    looserThanTwice += bound > 2.0 * exact + 1.0 ? 1 : 0;
                    ++cells;
                }
            }
        }
    }
    // The triangle inequality costs something, not everything: most bounds are within twice
    // the exact error (plus a metre).
    EXPECT_LT(looserThanTwice, cells / 4);
}

TEST(PatchErrors, CoarseCellsOfAPlaneHaveNoError) {
    const int n = 65;
    std::vector<float> h(n * n);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) h[y * n + x] = 0.5f * float(x) - 0.25f * float(y) + 7.0f;
    const GridView g{h.data(), n, n};
    std::vector<BlockErrors> lambda(64);
    patchBlockErrors(g, 8, lambda);
    for (const float bound : coarseCellErrors(g, 8, lambda)) EXPECT_LE(bound, 1e-12f);
}

}  // namespace
}  // namespace terrain::io

// The box the draw bounds a block's error over: each block's lowest and highest sample,
// within the patch's range; a no-data sample's height left out, a block with nothing left
// taking the patch's range.
TEST(PatchErrors, BlockHeightRangesAreEachBlocksOwnSamples) {
    constexpr int kBlockQuads = 2;
    constexpr int kSide = 5;  // 2 × 2 blocks of 2 × 2 quads
    std::vector<float> heights(kSide * kSide, 10.0f);
    heights[0] = 3.0f;               // block (0, 0) only
    heights[2] = 50.0f;              // the corner blocks (0, 0) and (1, 0) share
    heights[4 * kSide + 4] = 99.0f;  // beyond the patch's range: clamped to it
    heights[3 * kSide + 1] = NAN;    // block (0, 1): a sample without a height
    const terrain::io::GridView grid{heights.data(), kSide, kSide};
    std::vector<terrain::io::HeightRange> ranges(4);
    terrain::io::blockHeightRanges(grid, kBlockQuads, {0.0f, 60.0f}, ranges);
    EXPECT_EQ(ranges[0].low, 3.0f);
    EXPECT_EQ(ranges[0].high, 50.0f);
    EXPECT_EQ(ranges[1].low, 10.0f);
    EXPECT_EQ(ranges[1].high, 50.0f);
    EXPECT_EQ(ranges[2].low, 10.0f);
    EXPECT_EQ(ranges[2].high, 10.0f);
    EXPECT_EQ(ranges[3].low, 10.0f);
    EXPECT_EQ(ranges[3].high, 60.0f);

    std::vector<float> none(kSide * kSide, NAN);
    terrain::io::blockHeightRanges(terrain::io::GridView{none.data(), kSide, kSide}, kBlockQuads,
                                   {-5.0f, 7.0f}, ranges);
    for (const terrain::io::HeightRange& r : ranges) {
        EXPECT_EQ(r.low, -5.0f);
        EXPECT_EQ(r.high, 7.0f);
    }
}

// A tile's steepest rises between neighbouring samples, along its rows and its columns,
// skipping pairs with a sample without a height (what bounds a globe patch's slopes).
TEST(SampleRises, AreTheLargestDifferencesAlongRowsAndColumns) {
    constexpr int kSide = 3;
    std::vector<float> heights{0.0f, 2.0f, 1.0f,    // row 0: east rises 2, 1
                               5.0f, NAN,  1.5f,    // row 1
                               4.0f, 4.5f, -6.0f};  // row 2: east rises 0.5, 10.5
    const terrain::io::SampleRises rises =
        terrain::io::sampleRises(terrain::io::GridView{heights.data(), kSide, kSide});
    EXPECT_EQ(rises.east, 10.5f);
    EXPECT_EQ(rises.north, 7.5f);  // 1.5 → −6 down the last column
}
