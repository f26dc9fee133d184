// Globe patch bounding boxes: every point of the patch between its heights is inside (the
// LOD's distance and horizon culling rely on it), at every level and on the special places
// (poles, the antimeridian, cube corners), and the box is not much bigger than the patch. The
// same for native tiles and their windows (NativeOffset.h, NativeWindow), down to the deepest.
#include "terrain/globe/PatchBounds.h"
#include "terrain/globe/Wgs84.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <numbers>
#include <random>

namespace terrain::globe {
namespace {

struct Case {
    GlobePatchId id;
    double minHeight;
    double maxHeight;
};

std::vector<Case> cases() {
    std::vector<Case> result;
    for (const int level : {0, 1, 3, 7, 12, 18}) {
        const std::int64_t n = patchesPerFaceSide(level);
        for (int face = 0; face < kCubeFaces; ++face) {
            result.push_back({{face, level, 0, 0}, -500.0, 4000.0});            // a cube corner
            result.push_back({{face, level, n / 2, n / 2}, -11000.0, 9000.0});  // pole, 180°
            result.push_back({{face, level, n - 1, n / 3}, 0.0, 0.0});          // bare, edge
        }
    }
    return result;
}

TEST(PatchBounds, HoldEveryPointOfThePatchBetweenItsHeights) {
    std::mt19937_64 random(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (const Case& c : cases()) {
        const OrientedBox box = patchBounds(c.id, c.minHeight, c.maxHeight);
        for (int k = 0; k < 2000; ++k) {
            const bool onEdge = k < 400;  // corners and edges are where a box is tightest
            double u = unit(random);
            double v = unit(random);
            if (onEdge) (k % 2 ? u : v) = (k % 4 < 2) ? 0.0 : 1.0;
            const FacePoint p = patchPoint(c.id, u, v);
            const double height = c.minHeight + unit(random) * (c.maxHeight - c.minHeight);
            const glm::dvec3 point = Wgs84::pointAlongNormal(directionOf(p.face, p.s, p.t), height);
            ASSERT_EQ(distanceToBox(point, box), 0.0)
                << "face " << c.id.face << " level " << c.id.level << " u " << u << " v " << v
                << " h " << height;
        }
    }
}

// A native window's box (nativeTileBounds with a window) holds every point of the window's
// ground between its heights, on ETOPO's 20′ grid and an SRTM3 one, at the equator, 45° N,
// down to 89.7° S and across the antimeridian, from the whole tile (depth 0) to the deepest window;
// and a window's box is about its window's size, not its tile's.
TEST(PatchBounds, NativeWindowsBoxesHoldTheirGround) {
    std::mt19937_64 random(11);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (const double pixel : {1.0 / 3.0, 1.0 / 1200.0}) {
        for (const double north : {5.0, 50.0, -47.0, 1.0}) {
            NativeGridGeometry grid;
            grid.pixelLonDeg = grid.pixelLatDeg = pixel;
            grid.quads = 128;
            grid.westDeg = north == 1.0 ? 180.0 - 2.5 * 128.0 * pixel : -100.0;
            grid.northDeg = north;
            for (const int depth : {0, 1, 3, 8, NativeWindow::kMaxDepth}) {
                const std::int64_t last = (std::int64_t{1} << depth) - 1;
                const NativeWindow window{depth, last / 3, last};
                const OrientedBox box = nativeTileBounds(grid, 2, 0, -100.0, 3000.0, window);
                const double side = 128.0 * pixel * window.size() * Wgs84::kEquatorialRadius *
                                    std::numbers::pi / 180.0;
                EXPECT_LT(2.0 * box.halfExtents.x, 1.01 * side + 10.0) << "depth " << depth;
                for (int k = 0; k < 500; ++k) {
                    double u = unit(random), v = unit(random);
                    if (k < 100) (k % 2 ? u : v) = (k % 4 < 2) ? 0.0 : 1.0;
                    const glm::dvec2 at = grid.lonLatDeg(2, 0, window.u0() + u * window.size(),
                                                         window.v0() + v * window.size());
                    const double height = -100.0 + unit(random) * 3100.0;
                    const glm::dvec3 point =
                        Wgs84::pointAlongNormal(Wgs84::normalAt(at.y, at.x), height);
                    ASSERT_EQ(distanceToBox(point, box), 0.0)
                        << "pixel " << pixel << "° north " << north << " depth " << depth << " u "
                        << u << " v " << v;
                }
            }
        }
    }
}

// The reference point of a window's record (nearestNativeCoordinates with the window) is the
// camera's nadir where the window holds it, else the window's nearest point to it.
TEST(PatchBounds, NativeWindowsReferenceIsClampedToTheWindow) {
    NativeGridGeometry grid;
    grid.westDeg = -101.0;
    grid.northDeg = 41.0;
    grid.pixelLonDeg = grid.pixelLatDeg = 1.0 / 3.0;
    grid.quads = 128;
    const glm::dvec3 up = Wgs84::normalAt(40.0, -100.0);
    const glm::dvec2 nadir = nearestNativeCoordinates(grid, 0, 0, up);
    const NativeWindow holding{3, static_cast<std::int64_t>(std::floor(nadir.x * 8.0)),
                               static_cast<std::int64_t>(std::floor(nadir.y * 8.0))};
    const glm::dvec2 inside = nearestNativeCoordinates(grid, 0, 0, up, holding);
    EXPECT_DOUBLE_EQ(inside.x, nadir.x);
    EXPECT_DOUBLE_EQ(inside.y, nadir.y);
    const NativeWindow east{3, holding.i + 2, holding.j};
    const glm::dvec2 clamped = nearestNativeCoordinates(grid, 0, 0, up, east);
    EXPECT_DOUBLE_EQ(clamped.x, east.u0());
    EXPECT_DOUBLE_EQ(clamped.y, nadir.y);
}

TEST(PatchBounds, AreNotMuchBiggerThanThePatch) {
    for (const Case& c : cases()) {
        const OrientedBox box = patchBounds(c.id, c.minHeight, c.maxHeight);
        // A patch's sides are at most `side` long, but at a cube corner it is a rhombus with
        // 60° and 120° angles, whose long diagonal is √3 sides.
        const double side = maxSampleSpacing(c.id.level, 1);
        EXPECT_LE(box.halfExtents.x, 0.5 * std::sqrt(3.0) * side * 1.01 + 1.0)
            << "level " << c.id.level;
        EXPECT_LE(box.halfExtents.y, 0.5 * std::sqrt(3.0) * side * 1.01 + 1.0)
            << "level " << c.id.level;
        // Thickness: the heights plus the curvature over the patch's long diagonal (a chord of
        // √3 sides has a sagitta of 3·side²/8ρ), with a little for the padding.
        const double sagitta = 3.0 * side * side / (8.0 * Wgs84::kMinCurvatureRadius);
        EXPECT_LE(2.0 * box.halfExtents.z, (c.maxHeight - c.minHeight) + 1.1 * sagitta + 1.0)
            << "level " << c.id.level;
    }
}

TEST(PatchBounds, DistanceFromAboveIsTheHeightAboveTheTop) {
    // The patch whose north-west corner is the north pole: its box is square to the normal at
    // its centre, 7 km from the pole, so the pole's top is a sagitta (≈ 3.8 m) below the box top.
    const GlobePatchId id{static_cast<int>(CubeFace::North), 10, 512, 512};
    const OrientedBox box = patchBounds(id, 0.0, 2000.0);
    const glm::dvec3 camera = Wgs84::toEcef({90.0, 0.0, 12000.0});
    EXPECT_LE(distanceToBox(camera, box), 10000.0);
    EXPECT_GE(distanceToBox(camera, box), 10000.0 - 5.0);
    EXPECT_EQ(distanceToBox(Wgs84::toEcef({90.0, 0.0, 1000.0}), box), 0.0);
}

}  // namespace
}  // namespace terrain::globe
