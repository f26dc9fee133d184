// runtime::GeometrySplittingStrategy, Lee & Shin 2011 on the GPU, on rough synthetic rasters:
// the triangles that vertex splitting and triangle splitting write form a conforming mesh
// (every interior edge shared by exactly two triangles: no T-junction is left, so no crack)
// that covers the raster once when nothing is culled, also for rasters that are not
// 2^d + 1 a side; lists that overflow are grown and the frame built again (or, past the
// memory budget, keep what fits without writing beyond them); a smaller τ
// never draws fewer triangles; a raster over the memory budget is refused before anything is
// uploaded.
#include "GlTestFixture.h"
#include "GpuStrategyScenes.h"

#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/runtime/GeometrySplittingStrategy.h"

#include <gtest/gtest.h>

#include <glm/vec2.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <numbers>
#include <random>
#include <utility>
#include <vector>

namespace terrain::test {
namespace {

using runtime::GeometrySplittingStrategy;

using Triangles = std::vector<std::array<glm::ivec2, 3>>;

std::int64_t twiceArea(const std::array<glm::ivec2, 3>& t) {
    return std::llabs(static_cast<std::int64_t>(t[1].x - t[0].x) * (t[2].y - t[0].y) -
                      static_cast<std::int64_t>(t[1].y - t[0].y) * (t[2].x - t[0].x));
}

/// Every edge is shared by two triangles, or lies on the raster's border (one): no
/// T-junction. With `coversRaster`, the triangles cover (width − 1) × (height − 1) once.
void expectConforming(const Triangles& triangles, int width, int height, bool coversRaster) {
    std::map<std::pair<std::pair<int, int>, std::pair<int, int>>, int> edges;
    std::int64_t area = 0;
    for (const auto& t : triangles) {
        for (const glm::ivec2& v : t) {
            ASSERT_GE(v.x, 0);
            ASSERT_GE(v.y, 0);
            ASSERT_LE(v.x, width - 1) << "a vertex beyond the raster";
            ASSERT_LE(v.y, height - 1) << "a vertex beyond the raster";
        }
        const std::int64_t a = twiceArea(t);
        ASSERT_GT(a, 0) << "a degenerate triangle";
        area += a;
        for (int e = 0; e < 3; ++e) {
            std::pair p{t[e].x, t[e].y}, q{t[(e + 1) % 3].x, t[(e + 1) % 3].y};
            ++edges[{std::min(p, q), std::max(p, q)}];
        }
    }
    if (coversRaster) {
        EXPECT_EQ(area, 2LL * (width - 1) * (height - 1)) << "the triangles must tile the raster";
    }
    for (const auto& [edge, count] : edges) {
        const auto [p, q] = edge;
        const bool border = (p.first == q.first && (p.first == 0 || p.first == width - 1)) ||
                            (p.second == q.second && (p.second == 0 || p.second == height - 1));
        EXPECT_LE(count, 2) << "edge shared by more than two triangles";
        if (coversRaster) {
            EXPECT_EQ(count, border ? 1 : 2) << "edge (" << p.first << "," << p.second << ")–("
                                             << q.first << "," << q.second << "): a T-junction";
        }
    }
}

/// A conforming mesh with culled blocks: an edge used once is on the raster's border or on
/// the outline of what was culled, never with a vertex of another triangle inside it.
void expectNoTJunctions(const Triangles& triangles) {
    std::map<std::pair<int, int>, int> vertices;
    for (const auto& t : triangles)
        for (const glm::ivec2& v : t) ++vertices[{v.x, v.y}];
    for (const auto& t : triangles) {
        for (int e = 0; e < 3; ++e) {
            const glm::ivec2 a = t[e], b = t[(e + 1) % 3];
            const glm::ivec2 d = b - a;
            const int steps = std::gcd(std::abs(d.x), std::abs(d.y));
            for (int i = 1; i < steps; ++i) {
                const glm::ivec2 p = a + d / steps * i;
                EXPECT_EQ(vertices.count({p.x, p.y}), 0u)
                    << "T-vertex (" << p.x << "," << p.y << ") inside edge (" << a.x << "," << a.y
                    << ")–(" << b.x << "," << b.y << ")";
            }
        }
    }
}

class GeometrySplittingTest : public GlTest {};

TEST_F(GeometrySplittingTest, ATopDownViewIsAConformingMeshThatTilesTheRaster) {
    for (const auto& [width, height] : {std::pair{129, 129}, std::pair{100, 61}}) {
        SCOPED_TRACE(std::to_string(width) + " × " + std::to_string(height));
        const io::PyramidManifest manifest = manifestOf(width, height);
    const runtime::TerrainGeometry geometry(manifest);
        auto lee = GeometrySplittingStrategy::create(manifest, roughHeights(width, height, 1), 1.0);
        ASSERT_TRUE(lee) << lee.error().message;
        GeometrySplittingStrategy& s = *lee.value();
        // High enough for the whole raster to be in view, low enough to refine.
        s.beginFrame(cameraOver(geometry, 400.0, -89.0));
        const Triangles triangles = s.readTriangles();
        EXPECT_GT(triangles.size(), 2u) << "rough terrain is refined";
        EXPECT_EQ(triangles.size(), s.counts().triangles);
        expectConforming(triangles, width, height, true);
        expectNoTJunctions(triangles);
    }
}

TEST_F(GeometrySplittingTest, ObliqueViewsCullButLeaveNoTJunction) {
    constexpr int kSide = 257;
    const io::PyramidManifest manifest = manifestOf(kSide, kSide);
    const runtime::TerrainGeometry geometry(manifest);
    auto lee = GeometrySplittingStrategy::create(manifest, roughHeights(kSide, kSide, 2), 1.0);
    ASSERT_TRUE(lee) << lee.error().message;
    GeometrySplittingStrategy& s = *lee.value();
    for (const double pitch : {-10.0, -30.0}) {
        s.beginFrame(cameraOver(geometry, 60.0, pitch, {-60.0, 20.0}));
        const Triangles triangles = s.readTriangles();
        EXPECT_GT(triangles.size(), 10u);
        expectConforming(triangles, kSide, kSide, false);
        expectNoTJunctions(triangles);
    }
}

TEST_F(GeometrySplittingTest, ListsThatOverflowAreGrownAndTheFrameBuiltAgain) {
    constexpr int kSide = 513;
    const io::PyramidManifest manifest = manifestOf(kSide, kSide);
    const runtime::TerrainGeometry geometry(manifest);
    auto lee = GeometrySplittingStrategy::create(manifest, roughHeights(kSide, kSide, 3), 0.25);
    ASSERT_TRUE(lee) << lee.error().message;
    GeometrySplittingStrategy& s = *lee.value();
    const runtime::Camera camera = cameraOver(geometry, 300.0, -89.0);
    s.beginFrame(camera);
    EXPECT_GT(s.counts().builds, 1) << "the first lists hold 2^16 triangles; this view needs more";
    EXPECT_GT(s.counts().triangles, std::uint64_t{1} << 16);
    const Triangles first = s.readTriangles();
    expectConforming(first, kSide, kSide, false);  // the raster's corners are out of view
    expectNoTJunctions(first);
    s.beginFrame(camera);
    EXPECT_EQ(s.counts().builds, 1) << "grown lists are kept";
    EXPECT_EQ(s.counts().triangles, first.size());
}

TEST_F(GeometrySplittingTest, ASmallerThresholdNeverDrawsFewerTriangles) {
    constexpr int kSide = 257;
    const io::PyramidManifest manifest = manifestOf(kSide, kSide);
    const runtime::TerrainGeometry geometry(manifest);
    auto lee = GeometrySplittingStrategy::create(manifest, roughHeights(kSide, kSide, 4), 1.0);
    ASSERT_TRUE(lee) << lee.error().message;
    GeometrySplittingStrategy& s = *lee.value();
    const runtime::Camera camera = cameraOver(geometry, 80.0, -25.0, {0.0, 60.0});
    std::uint64_t previous = 0;
    for (const double tau : {16.0, 4.0, 1.0, 0.5}) {
        s.setErrorPx(tau);
        s.beginFrame(camera);
        EXPECT_GE(s.counts().triangles, previous) << "τ = " << tau;
        previous = s.counts().triangles;
    }
    EXPECT_GT(previous, 1000u);
}

TEST_F(GeometrySplittingTest, AViewWhoseListsPassTheBudgetDrawsWhatFits) {
    constexpr int kSide = 513;
    const io::PyramidManifest manifest = manifestOf(kSide, kSide);
    const runtime::TerrainGeometry geometry(manifest);
    std::size_t initialBytes = 0;
    {
        auto roomy =
            GeometrySplittingStrategy::create(manifest, roughHeights(kSide, kSide, 3), 1.0);
        ASSERT_TRUE(roomy) << roomy.error().message;
        initialBytes = roomy.value()->memoryBytes();
    }
    auto tight = GeometrySplittingStrategy::create(manifest, roughHeights(kSide, kSide, 3), 0.25,
                                                   initialBytes);
    ASSERT_TRUE(tight) << tight.error().message;
    GeometrySplittingStrategy& s = *tight.value();
    s.beginFrame(cameraOver(geometry, 300.0, -89.0));
    EXPECT_EQ(s.counts().builds, 1) << "nothing can grow";
    EXPECT_EQ(s.memoryBytes(), initialBytes);
    EXPECT_GT(s.counts().triangles, 0u);
    EXPECT_LE(s.counts().triangles, std::uint64_t{1} << 16) << "the first list's capacity";
    EXPECT_EQ(s.readTriangles().size(), s.counts().triangles);
}

TEST_F(GeometrySplittingTest, ARasterOverTheMemoryBudgetIsRefused) {
    constexpr int kSide = 257;
    auto lee = GeometrySplittingStrategy::create(manifestOf(kSide, kSide),
                                                 roughHeights(kSide, kSide, 5), 1.0, 100'000);
    ASSERT_FALSE(lee);
    EXPECT_NE(lee.error().message.find("MiB"), std::string::npos) << lee.error().message;
}

}  // namespace
}  // namespace terrain::test
