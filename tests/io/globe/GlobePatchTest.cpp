// The face quadtrees and their seams: neighbours across every side (the 12 cube edges
// included) find each other back, shared edge samples are bit-identical from both patches,
// and the flat-triangle bound really bounds how far the ellipsoid strays from a sample grid.
#include "terrain/globe/GlobePatch.h"
#include "terrain/globe/Wgs84.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <set>
#include <utility>

namespace terrain::globe {
namespace {

constexpr std::array<PatchSide, 4> kSides{PatchSide::Left, PatchSide::Right, PatchSide::Top,
                                          PatchSide::Bottom};

/// Sample (i, j) of the patch's side, k along it (in the face's own direction of that side).
std::pair<int, int> sideSample(PatchSide side, int quads, int k) {
    switch (side) {
        case PatchSide::Left:
            return {0, k};
        case PatchSide::Right:
            return {quads, k};
        case PatchSide::Top:
            return {k, 0};
        case PatchSide::Bottom:
            break;
    }
    return {k, quads};
}

TEST(GlobePatch, EveryFaceHasFourDistinctNeighbourFacesAndEveryCubeEdgeIsSharedOnce) {
    std::set<std::pair<int, int>> edges;
    for (int face = 0; face < kCubeFaces; ++face) {
        std::set<int> neighbours;
        for (PatchSide side : kSides) {
            const PatchNeighbour n = neighbourOf({face, 0, 0, 0}, side);
            EXPECT_NE(n.id.face, face);
            EXPECT_NE(faceFrame(n.id.face).normal, -faceFrame(face).normal);
            neighbours.insert(n.id.face);
            edges.insert({std::min(face, n.id.face), std::max(face, n.id.face)});
        }
        EXPECT_EQ(neighbours.size(), 4u) << "face " << face;
    }
    EXPECT_EQ(edges.size(), 12u);
}

TEST(GlobePatch, NeighboursFindEachOtherBackOnEveryLevel) {
    for (int level = 0; level <= 3; ++level) {
        const std::int64_t n = patchesPerFaceSide(level);
        for (int face = 0; face < kCubeFaces; ++face) {
            for (std::int64_t y = 0; y < n; ++y) {
                for (std::int64_t x = 0; x < n; ++x) {
                    const GlobePatchId id{face, level, x, y};
                    for (PatchSide side : kSides) {
                        const PatchNeighbour there = neighbourOf(id, side);
                        const PatchNeighbour back = neighbourOf(there.id, there.side);
                        ASSERT_EQ(back.id, id) << "face " << face << " level " << level;
                        ASSERT_EQ(back.side, side);
                        ASSERT_EQ(back.reversed, there.reversed);
                    }
                }
            }
        }
    }
}

TEST(GlobePatch, SharedEdgeSamplesAreBitIdenticalFromBothPatches) {
    constexpr int kQuads = 16;
    int crossFaceEdges = 0;
    for (int level = 0; level <= 3; ++level) {
        const std::int64_t n = patchesPerFaceSide(level);
        for (int face = 0; face < kCubeFaces; ++face) {
            for (std::int64_t y = 0; y < n; ++y) {
                for (std::int64_t x = 0; x < n; ++x) {
                    const GlobePatchId id{face, level, x, y};
                    for (PatchSide side : kSides) {
                        const PatchNeighbour there = neighbourOf(id, side);
                        crossFaceEdges += there.id.face != face;
                        for (int k = 0; k <= kQuads; ++k) {
                            const auto [i, j] = sideSample(side, kQuads, k);
                            const auto [ni, nj] =
                                sideSample(there.side, kQuads, there.reversed ? kQuads - k : k);
                            const glm::dvec3 mine = patchSampleDirection(id, kQuads, i, j);
                            const glm::dvec3 theirs =
                                patchSampleDirection(there.id, kQuads, ni, nj);
                            ASSERT_TRUE(mine == theirs)
                                << "face " << face << " level " << level << " patch " << x << ","
                                << y << " side " << int(side) << " sample " << k;
                            ASSERT_TRUE(Wgs84::pointAlongNormal(mine, 1234.5) ==
                                        Wgs84::pointAlongNormal(theirs, 1234.5));
                        }
                    }
                }
            }
        }
    }
    EXPECT_EQ(crossFaceEdges, 24 * (1 + 2 + 4 + 8));  // 6 faces · 4 sides · 2^level patches
}

// The builders' table of a patch's sample directions (one tangent a column and a row) gives
// patchSampleDirection's directions to the bit, apron included, on every face and at the
// face's corners, where cubeCoordinate sets the edge exactly.
TEST(GlobePatch, SampleDirectionTableIsPatchSampleDirectionBitForBit) {
    constexpr int kQuads = 16;
    for (int face = 0; face < kCubeFaces; ++face) {
        for (const GlobePatchId id : {GlobePatchId{face, 0, 0, 0}, GlobePatchId{face, 5, 17, 30},
                                      GlobePatchId{face, 12, 4095, 0}}) {
            const PatchSampleDirections table(id, kQuads, -1, kQuads + 1);
            for (int j = -1; j <= kQuads + 1; ++j)
                for (int i = -1; i <= kQuads + 1; ++i)
                    ASSERT_TRUE(table(i, j) == patchSampleDirection(id, kQuads, i, j))
                        << "face " << face << " level " << id.level << " sample " << i << "," << j;
        }
    }
}

// Measure the geodetic height of points inside the flat triangles of patch sample grids: the
// bound must hold, and be within 3× of the worst case seen (so Err(P) is not padded blindly).
TEST(GlobePatch, FlatTriangleBoundHoldsOnTheEllipsoid) {
    constexpr int kQuads = 128;
    for (const int level : {0, 2, 6, 10}) {
        double worst = 0.0;
        for (int face = 0; face < kCubeFaces; ++face) {
            const std::int64_t last = patchesPerFaceSide(level) - 1;
            for (const auto& [x, y] : {std::pair{std::int64_t{0}, std::int64_t{0}},
                                       std::pair{last / 2, last / 2}, std::pair{last, 0l}}) {
                const GlobePatchId id{face, level, x, y};
                for (int j = 0; j < kQuads; j += 7) {
                    for (int i = 0; i < kQuads; i += 7) {
                        const glm::dvec3 a =
                            Wgs84::pointAlongNormal(patchSampleDirection(id, kQuads, i, j), 0.0);
                        const glm::dvec3 b = Wgs84::pointAlongNormal(
                            patchSampleDirection(id, kQuads, i + 1, j), 0.0);
                        const glm::dvec3 c = Wgs84::pointAlongNormal(
                            patchSampleDirection(id, kQuads, i, j + 1), 0.0);
                        const glm::dvec3 d = Wgs84::pointAlongNormal(
                            patchSampleDirection(id, kQuads, i + 1, j + 1), 0.0);
                        for (const glm::dvec3& inside :
                             {(a + b + c) / 3.0, (b + c + d) / 3.0, (b + c) / 2.0}) {
                            worst = std::max(worst, std::abs(Wgs84::toGeodetic(inside).height));
                        }
                    }
                }
            }
        }
        const double bound = flatTriangleErrorBound(maxSampleSpacing(level, kQuads));
        std::cout << "level " << level << ": flat-triangle error " << worst << " m, bound " << bound
                  << " m\n";
        EXPECT_LE(worst, bound);
        EXPECT_GT(worst, bound / 3.0);
    }
}

}  // namespace
}  // namespace terrain::globe
