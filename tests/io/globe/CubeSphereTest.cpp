// The cube-sphere's face projection: exact face edges, odd symmetry (what makes shared edges
// bit-identical), round trips, poles and the antimeridian as interior points, and the spacing
// of a regular face grid on the WGS84 ellipsoid within the 1.5× the design asks for.
#include "terrain/globe/CubeSphere.h"
#include "terrain/globe/GlobePatch.h"
#include "terrain/globe/Wgs84.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <iostream>

namespace terrain::globe {
namespace {

TEST(CubeSphere, CubeCoordinateIsExactAtTheEdgesAndOddSymmetric) {
    EXPECT_EQ(cubeCoordinate(0.0), -1.0);
    EXPECT_EQ(cubeCoordinate(1.0), 1.0);
    EXPECT_EQ(cubeCoordinate(0.5), 0.0);
    for (int i = 0; i <= 4096; ++i) {
        const double s = i / 4096.0;
        ASSERT_EQ(cubeCoordinate(1.0 - s), -cubeCoordinate(s)) << "s = " << s;
        ASSERT_NEAR(faceCoordinate(cubeCoordinate(s)), s, 1e-15);
    }
}

TEST(CubeSphere, FacePointsRoundTripThroughDirections) {
    for (int face = 0; face < kCubeFaces; ++face) {
        for (int j = 1; j < 64; ++j) {
            for (int i = 1; i < 64; ++i) {
                const double s = i / 64.0;
                const double t = j / 64.0;
                const glm::dvec3 d = directionOf(face, s, t);
                ASSERT_NEAR(glm::length(d), 1.0, 1e-15);
                const FacePoint back = facePointOf(d);
                ASSERT_EQ(back.face, face);
                ASSERT_NEAR(back.s, s, 1e-14);
                ASSERT_NEAR(back.t, t, 1e-14);
            }
        }
    }
}

TEST(CubeSphere, PolesAndTheAntimeridianAreFaceCentres) {
    const auto atCentre = [](int face) {
        return Wgs84::geodeticOfNormal(directionOf(face, 0.5, 0.5));
    };
    EXPECT_DOUBLE_EQ(atCentre(static_cast<int>(CubeFace::North)).latitudeDeg, 90.0);
    EXPECT_DOUBLE_EQ(atCentre(static_cast<int>(CubeFace::South)).latitudeDeg, -90.0);
    EXPECT_DOUBLE_EQ(std::abs(atCentre(static_cast<int>(CubeFace::NegativeX)).longitudeDeg), 180.0);
    EXPECT_DOUBLE_EQ(atCentre(static_cast<int>(CubeFace::PositiveY)).longitudeDeg, 90.0);
    // Both sides of the antimeridian are on one face, next to each other.
    const FacePoint east = facePointOf(Wgs84::normalAt(10.0, 179.999));
    const FacePoint west = facePointOf(Wgs84::normalAt(10.0, -179.999));
    EXPECT_EQ(east.face, static_cast<int>(CubeFace::NegativeX));
    EXPECT_EQ(west.face, east.face);
    EXPECT_NEAR(east.s, west.s, 1e-4);
}

TEST(CubeSphere, FacesRunEastAndSouthOnTheSides) {
    for (int face = 0; face < 4; ++face) {
        const Geodetic a = Wgs84::geodeticOfNormal(directionOf(face, 0.4, 0.5));
        const Geodetic b = Wgs84::geodeticOfNormal(directionOf(face, 0.6, 0.4));
        EXPECT_GT(std::remainder(b.longitudeDeg - a.longitudeDeg, 360.0), 0.0) << "face " << face;
        EXPECT_GT(b.latitudeDeg, a.latitudeDeg) << "face " << face;
    }
}

// The spacing of a regular 256 × 256 grid of every face, measured between neighbouring
// ellipsoid points: the largest over the smallest must stay under 1.5 (a gnomonic cube
// varies about 5×), and the largest angle must stay under the bound the LOD relies on.
TEST(CubeSphere, GridSpacingVariesLessThanOneAndAHalfTimesOverEveryFace) {
    constexpr int kQuads = 256;
    double smallest = 1e300;
    double largest = 0.0;
    double largestAngle = 0.0;
    for (int face = 0; face < kCubeFaces; ++face) {
        for (int j = 0; j <= kQuads; ++j) {
            for (int i = 0; i <= kQuads; ++i) {
                const glm::dvec3 d = directionOf(face, double(i) / kQuads, double(j) / kQuads);
                const glm::dvec3 p = Wgs84::pointAlongNormal(d, 0.0);
                for (const auto& [di, dj] : {std::pair{1, 0}, std::pair{0, 1}}) {
                    if (i + di > kQuads || j + dj > kQuads) continue;
                    const glm::dvec3 dn =
                        directionOf(face, double(i + di) / kQuads, double(j + dj) / kQuads);
                    const double spacing = glm::distance(p, Wgs84::pointAlongNormal(dn, 0.0));
                    smallest = std::min(smallest, spacing);
                    largest = std::max(largest, spacing);
                    largestAngle =
                        std::max(largestAngle, std::acos(std::min(1.0, glm::dot(d, dn))));
                }
            }
        }
    }
    std::cout << "face grid spacing: " << smallest << " m to " << largest << " m, ratio "
              << largest / smallest << "\n";
    EXPECT_LT(largest / smallest, 1.5);
    // The bound is attained on the face's centre lines, where the direction turns uniformly
    // with α: equal up to rounding.
    EXPECT_LE(largestAngle, maxSampleAngle(0, kQuads) * (1.0 + 1e-9));
    EXPECT_LE(largest, maxSampleSpacing(0, kQuads));
}

}  // namespace
}  // namespace terrain::globe
