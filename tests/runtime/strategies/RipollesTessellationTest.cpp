// runtime::RipollesStrategy, Ripolles et al.'s GPU tessellation, on rough synthetic rasters:
// the tessellation a view settles on is conforming (every interior edge shared by exactly two
// triangles: the patterns leave no T-vertex) and tiles the padded square once; the coherent
// method (one step a frame from the previous tessellation, refining and coarsening) reaches
// exactly the tessellation that starting again from the input mesh reaches, also after
// flying away and back (coarsening restores the families' parents); a smaller τ never
// draws fewer triangles; every step changes the tessellation by one level at most and keeps
// it a cover of the square, overlapping nowhere.
#include "GlTestFixture.h"
#include "GpuStrategyScenes.h"

#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/runtime/RipollesStrategy.h"

#include <gtest/gtest.h>

#include <glm/vec2.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <tuple>
#include <vector>

namespace terrain::test {
namespace {

using runtime::RipollesStrategy;
using Triangles = std::vector<std::array<glm::vec2, 3>>;

double twiceArea(const std::array<glm::vec2, 3>& t) {
    return std::abs(static_cast<double>(t[1].x - t[0].x) * (t[2].y - t[0].y) -
                    static_cast<double>(t[1].y - t[0].y) * (t[2].x - t[0].x));
}

/// Every edge shared by two triangles, or on the square's border: no T-vertex; the triangles
/// cover the square of `side` samples once.
void expectConformingTiling(const Triangles& triangles, float side) {
    using Point = std::pair<float, float>;
    std::map<std::pair<Point, Point>, int> edges;
    double area = 0.0;
    for (const auto& t : triangles) {
        const double a = twiceArea(t);
        ASSERT_GT(a, 0.0) << "a degenerate triangle";
        area += a;
        for (int e = 0; e < 3; ++e) {
            const Point p{t[e].x, t[e].y}, q{t[(e + 1) % 3].x, t[(e + 1) % 3].y};
            ++edges[{std::min(p, q), std::max(p, q)}];
        }
    }
    EXPECT_DOUBLE_EQ(area, 2.0 * side * side) << "the triangles must tile the square once";
    int bad = 0;
    for (const auto& [edge, count] : edges) {
        const auto [p, q] = edge;
        const bool border = (p.first == q.first && (p.first == 0.0f || p.first == side)) ||
                            (p.second == q.second && (p.second == 0.0f || p.second == side));
        if (count != (border ? 1 : 2) && bad++ < 5)
            ADD_FAILURE() << "edge (" << p.first << "," << p.second << ")–(" << q.first << ","
                          << q.second << ") shared by " << count << ": a T-vertex";
    }
    EXPECT_EQ(bad, 0);
}

/// The triangles as a sorted list, so that two tessellations can be compared.
std::vector<std::array<float, 6>> sorted(const Triangles& triangles) {
    std::vector<std::array<float, 6>> out;
    for (const auto& t : triangles) {
        std::array<std::pair<float, float>, 3> v{
            {{t[0].x, t[0].y}, {t[1].x, t[1].y}, {t[2].x, t[2].y}}};
        std::sort(v.begin(), v.end());
        out.push_back({v[0].first, v[0].second, v[1].first, v[1].second, v[2].first, v[2].second});
    }
    std::sort(out.begin(), out.end());
    return out;
}

class RipollesTessellationTest : public GlTest {};

TEST_F(RipollesTessellationTest, ASettledViewIsAConformingTilingOfTheSquare) {
    for (const auto& [width, height] : {std::pair{129, 129}, std::pair{100, 61}}) {
        SCOPED_TRACE(std::to_string(width) + " × " + std::to_string(height));
        const io::PyramidManifest manifest = manifestOf(width, height);
    const runtime::TerrainGeometry geometry(manifest);
        auto made = RipollesStrategy::create(manifest, roughHeights(width, height, 1), 8.0);
        ASSERT_TRUE(made) << made.error().message;
        RipollesStrategy& s = *made.value();
        const runtime::Camera camera = cameraOver(geometry, 80.0, -30.0, {0.0, -40.0});
        ASSERT_TRUE(s.settle(camera, std::chrono::seconds(60)));
        EXPECT_GT(s.counts().triangles, 16u) << "a near view is refined";
        const Triangles triangles = s.readTriangles();
        EXPECT_EQ(triangles.size(), s.counts().triangles);
        expectConformingTiling(triangles, 128.0f);  // both pad to 2^7 quads
    }
}

TEST_F(RipollesTessellationTest, CoherentStepsReachWhatStartingAgainReaches) {
    constexpr int kSide = 257;
    const io::PyramidManifest manifest = manifestOf(kSide, kSide);
    const runtime::TerrainGeometry geometry(manifest);
    const std::vector<float> heights = roughHeights(kSide, kSide, 2);
    auto coherent = RipollesStrategy::create(manifest, heights, 6.0);
    auto fresh = RipollesStrategy::create(manifest, heights, 6.0, {.coherence = false});
    ASSERT_TRUE(coherent) << coherent.error().message;
    ASSERT_TRUE(fresh) << fresh.error().message;
    // A flight that refines near one corner, moves across, climbs away (coarsening most of
    // the tessellation) and comes back down elsewhere.
    const std::vector<runtime::Camera> flight = {cameraOver(geometry, 40.0, -20.0, {-80.0, -80.0}),
                                                 cameraOver(geometry, 40.0, -20.0, {60.0, 20.0}),
                                                 cameraOver(geometry, 900.0, -60.0),
                                                 cameraOver(geometry, 30.0, -10.0, {90.0, -60.0})};
    for (std::size_t i = 0; i < flight.size(); ++i) {
        SCOPED_TRACE("pose " + std::to_string(i));
        // Step by step, as frames would: every intermediate tessellation still covers the
        // square exactly once (a family is replaced only by its own parent or children).
        int steps = 0;
        while (coherent.value()->step(flight[i])) {
            ASSERT_LT(++steps, 400) << "the tessellation never settles";
            double area = 0.0;
            for (const auto& t : coherent.value()->readTriangles()) area += twiceArea(t);
            ASSERT_DOUBLE_EQ(area, 2.0 * 256.0 * 256.0) << "step " << steps;
        }
        fresh.value()->beginFrame(flight[i]);
        const Triangles a = coherent.value()->readTriangles();
        const Triangles b = fresh.value()->readTriangles();
        EXPECT_EQ(a.size(), b.size());
        EXPECT_TRUE(sorted(a) == sorted(b)) << "the coherent tessellation differs from a fresh one";
        expectConformingTiling(a, 256.0f);
    }
}

TEST_F(RipollesTessellationTest, OneStepAFrameMovesByOneLevelAtMost) {
    constexpr int kSide = 257;
    const io::PyramidManifest manifest = manifestOf(kSide, kSide);
    const runtime::TerrainGeometry geometry(manifest);
    auto made = RipollesStrategy::create(manifest, roughHeights(kSide, kSide, 3), 4.0);
    ASSERT_TRUE(made) << made.error().message;
    RipollesStrategy& s = *made.value();
    const runtime::Camera camera = cameraOver(geometry, 40.0, -20.0);
    // From the input mesh every step can at most quadruple the triangles.
    std::uint64_t previous = s.counts().triangles;
    int steps = 0;
    while (s.step(camera)) {
        EXPECT_LE(s.counts().triangles, 4 * previous);
        previous = s.counts().triangles;
        ASSERT_LT(++steps, 200) << "the tessellation never settles";
    }
    EXPECT_GT(steps, 4) << "one step a frame: the near view takes several";
}

TEST_F(RipollesTessellationTest, ASmallerThresholdNeverDrawsFewerTriangles) {
    constexpr int kSide = 257;
    const io::PyramidManifest manifest = manifestOf(kSide, kSide);
    const runtime::TerrainGeometry geometry(manifest);
    auto made = RipollesStrategy::create(manifest, roughHeights(kSide, kSide, 4), 32.0);
    ASSERT_TRUE(made) << made.error().message;
    RipollesStrategy& s = *made.value();
    const runtime::Camera camera = cameraOver(geometry, 60.0, -25.0, {0.0, 40.0});
    std::uint64_t previous = 0;
    for (const double tau : {32.0, 16.0, 8.0, 4.0}) {
        s.setErrorPx(tau);
        ASSERT_TRUE(s.settle(camera, std::chrono::seconds(60)));
        EXPECT_GE(s.counts().triangles, previous) << "τ = " << tau;
        previous = s.counts().triangles;
    }
    EXPECT_GT(previous, 1000u);
}

}  // namespace
}  // namespace terrain::test
