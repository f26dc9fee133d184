// faceTriangleErrorBound against the ellipsoid by brute force: flat triangles drawn between
// a cube face cell's samples (either diagonal, as the tessellator may choose), each of their
// points taken back to its face coordinates and height, and that height compared with the
// triangle's heights interpolated linearly at those face coordinates (the surface a virtual
// patch or a finest face patch stands for). Cells at a face's centre, near its edge and near
// its corner, of face levels 2 to 13, from flat to corners six cell sides apart in height.
#include "terrain/globe/CubeSphere.h"
#include "terrain/globe/GlobePatch.h"
#include "terrain/globe/Wgs84.h"

#include <gtest/gtest.h>
#include <glm/vec2.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <random>

namespace terrain::globe {
namespace {

constexpr int kQuads = 128;

struct Cell {
    int face = 0;
    double s0 = 0.0, t0 = 0.0, step = 0.0;  // corner (s0, t0), side `step` in face coordinates
    std::array<double, 4> heights{};        // at (0,0), (1,0), (1,1), (0,1) in cells
};

// The largest |drawn − interpolated| height over the cell's two triangles, for one diagonal.
double drawnError(const Cell& c, bool otherDiagonal) {
    const std::array<glm::dvec2, 4> at{glm::dvec2{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    std::array<glm::dvec3, 4> corner{};
    for (std::size_t k = 0; k < 4; ++k)
        corner[k] = Wgs84::pointAlongNormal(
            directionOf(c.face, c.s0 + at[k].x * c.step, c.t0 + at[k].y * c.step), c.heights[k]);
    // Triangles as corner indices: (0, 1, 2) and (0, 2, 3), or (0, 1, 3) and (1, 2, 3).
    const std::array<std::array<int, 3>, 2> triangles =
        otherDiagonal ? std::array<std::array<int, 3>, 2>{{{0, 1, 3}, {1, 2, 3}}}
                      : std::array<std::array<int, 3>, 2>{{{0, 1, 2}, {0, 2, 3}}};
    constexpr int kSteps = 32;
    double worst = 0.0;
    for (const auto& tri : triangles) {
        const auto A = static_cast<std::size_t>(tri[0]), B = static_cast<std::size_t>(tri[1]),
                   C = static_cast<std::size_t>(tri[2]);
        for (int j = 0; j <= kSteps; ++j)
            for (int i = 0; i + j <= kSteps; ++i) {
                const double b = double(i) / kSteps, g = double(j) / kSteps, a = 1.0 - b - g;
                const glm::dvec3 drawn = a * corner[A] + b * corner[B] + g * corner[C];
                const Geodetic place = Wgs84::toGeodetic(drawn);
                const FacePoint p =
                    facePointOf(Wgs84::normalAt(place.latitudeDeg, place.longitudeDeg));
                if (p.face != c.face) continue;  // the cells below stay clear of face edges
                const glm::dvec2 uv{(p.s - c.s0) / c.step, (p.t - c.t0) / c.step};
                // The triangle's heights, linear in face coordinates, at uv.
                const glm::dvec2 e1 = at[B] - at[A], e2 = at[C] - at[A], d = uv - at[A];
                const double det = e1.x * e2.y - e1.y * e2.x;
                const double wb = (d.x * e2.y - d.y * e2.x) / det;
                const double wc = (e1.x * d.y - e1.y * d.x) / det;
                const double interpolated = c.heights[A] + wb * (c.heights[B] - c.heights[A]) +
                                            wc * (c.heights[C] - c.heights[A]);
                worst = std::max(worst, std::abs(place.height - interpolated));
            }
    }
    return worst;
}

TEST(FaceCellError, BoundsTheDrawnTrianglesAgainstTheFaceInterpolationOnTheEllipsoid) {
    std::mt19937 random(11);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    double worstRatio = 0.0, worstSagRatio = 0.0;
    // (Deeper, a cell's sag nears the doubles' own rounding at the Earth's radius.)
    for (const int level : {2, 6, 10, 13}) {
        const double step = 1.0 / (double(patchesPerFaceSide(level)) * kQuads);
        const double angle = maxSampleAngle(level, kQuads);
        const double side = angle * Wgs84::kEquatorialRadius;
        // A face's centre, near an edge, near a corner (a cell clear of the edge).
        for (const glm::dvec2 place : {glm::dvec2{0.5, 0.5}, {0.5, 0.01}, {0.985, 0.985}}) {
            for (const double rise : {0.0, 0.2, 1.0, 3.0}) {  // corners ± rise cell sides
                for (int trial = 0; trial < 6; ++trial) {
                    Cell c;
                    c.face = trial % kCubeFaces;
                    c.step = step;
                    c.s0 = std::floor(place.x / step) * step;
                    c.t0 = std::floor(place.y / step) * step;
                    const double base = -400.0 + 8400.0 * unit(random);
                    for (double& h : c.heights) h = base + (2.0 * unit(random) - 1.0) * rise * side;
                    const auto& h = c.heights;
                    const double riseS = std::max(std::abs(h[1] - h[0]), std::abs(h[2] - h[3]));
                    const double riseT = std::max(std::abs(h[3] - h[0]), std::abs(h[2] - h[1]));
                    const double bound = faceTriangleErrorBound(angle, riseS, riseT);
                    for (const bool other : {false, true}) {
                        const double error = drawnError(c, other);
                        ASSERT_LE(error, bound) << "level " << level << " at (" << place.x << ", "
                                                << place.y << "), rise " << rise;
                        worstRatio = std::max(worstRatio, error / bound);
                        worstSagRatio = std::max(
                            worstSagRatio,
                            error / flatTriangleErrorBound(angle * Wgs84::kMaxCurvatureRadius));
                    }
                }
            }
        }
    }
    std::cout << "largest error / bound " << worstRatio << ", / the sag alone " << worstSagRatio
              << "\n";
    EXPECT_GT(worstRatio, 0.2) << "not vacuous";
    EXPECT_GT(worstSagRatio, 2.0) << "the sag alone was no bound on a slope";
}

TEST(FaceCellError, WithoutARiseItIsTheSagAlone) {
    const double angle = maxSampleAngle(9, kQuads);
    EXPECT_EQ(faceTriangleErrorBound(angle, 0.0, 0.0),
              flatTriangleErrorBound(angle * Wgs84::kMaxCurvatureRadius));
    EXPECT_GT(faceTriangleErrorBound(angle, 10.0, 0.0), faceTriangleErrorBound(angle, 1.0, 0.0));
}

}  // namespace
}  // namespace terrain::globe
