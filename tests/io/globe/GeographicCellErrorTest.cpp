// geographicTriangleErrorBound against the ellipsoid by brute force: flat triangles drawn
// between a longitude/latitude cell's three samples (NW–SE, as the sources' own triangles),
// each of their points taken back to latitude, longitude and height, and that height compared
// with the source's triangle at the point's own latitude and longitude (what GlobeTruth
// measures). Cells of 20′ (ETOPO), 20′ simplified by 16, 3″ and 1″, from the equator to 89.7°,
// from flat to corners six cell sides apart in height.
#include "terrain/globe/GlobePatch.h"
#include "terrain/globe/Wgs84.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <numbers>
#include <random>

namespace terrain::globe {
namespace {

constexpr double kRadian = std::numbers::pi / 180.0;

struct Cell {
    double northDeg = 0.0;            // the cell's north-west sample is (northDeg, 0)
    double stepDeg = 0.0;             // Δφ = Δλ
    std::array<double, 4> heights{};  // NW, NE, SE, SW
};

// The source's height at a place: the cell's NW–SE triangles (u east, v south, in cells),
// extended linearly past the cell.
double sourceHeight(const Cell& c, double latitudeDeg, double longitudeDeg) {
    const double u = longitudeDeg / c.stepDeg, v = (c.northDeg - latitudeDeg) / c.stepDeg;
    const auto& h = c.heights;
    return u >= v ? h[0] + u * (h[1] - h[0]) + v * (h[2] - h[1])
                  : h[0] + v * (h[3] - h[0]) + u * (h[2] - h[3]);
}

// The largest |drawn − source| height over both flat triangles, on a 40 × 40 lattice of each.
double drawnError(const Cell& c) {
    std::array<glm::dvec3, 4> corner{};
    const std::array<double, 4> lat{c.northDeg, c.northDeg, c.northDeg - c.stepDeg,
                                    c.northDeg - c.stepDeg};
    const std::array<double, 4> lon{0.0, c.stepDeg, c.stepDeg, 0.0};
    for (std::size_t k = 0; k < 4; ++k) corner[k] = Wgs84::toEcef({lat[k], lon[k], c.heights[k]});
    constexpr int kSteps = 40;
    double worst = 0.0;
    for (int j = 0; j <= kSteps; ++j) {
        for (int i = 0; i <= kSteps; ++i) {
            const double u = double(i) / kSteps, v = double(j) / kSteps;
            // NW–NE–SE where u ≥ v, NW–SW–SE otherwise.
            const glm::dvec3 drawn =
                u >= v ? corner[0] + u * (corner[1] - corner[0]) + v * (corner[2] - corner[1])
                       : corner[0] + v * (corner[3] - corner[0]) + u * (corner[2] - corner[3]);
            const Geodetic place = Wgs84::toGeodetic(drawn);
            worst = std::max(worst, std::abs(place.height - sourceHeight(c, place.latitudeDeg,
                                                                         place.longitudeDeg)));
        }
    }
    return worst;
}

GeographicCells shapeOf(const Cell& c) {
    const auto& h = c.heights;
    GeographicCells cells;
    cells.lonStepRad = cells.latStepRad = c.stepDeg * kRadian;
    cells.northRad = c.northDeg * kRadian;
    cells.southRad = (c.northDeg - c.stepDeg) * kRadian;
    cells.riseEastM = std::max(std::abs(h[1] - h[0]), std::abs(h[2] - h[3]));
    cells.riseNorthM = std::max(std::abs(h[3] - h[0]), std::abs(h[2] - h[1]));
    cells.minHeightM = *std::min_element(h.begin(), h.end());
    cells.maxHeightM = *std::max_element(h.begin(), h.end());
    return cells;
}

TEST(GeographicCellError, BoundsTheDrawnTrianglesAgainstTheSourcesOnTheEllipsoid) {
    std::mt19937 random(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    struct Spacing {
        const char* name;
        double stepDeg;
    };
    double worstRatio = 0.0, worstOldRatio = 0.0;
    for (const Spacing spacing : {Spacing{"20' x 16", 16.0 / 3.0}, Spacing{"20'", 1.0 / 3.0},
                                  Spacing{"3\"", 3.0 / 3600.0}, Spacing{"1\"", 1.0 / 3600.0}}) {
        for (const double latitude : {0.0, 40.0, 80.0, 89.0, 89.7}) {
            for (const double rise : {0.0, 0.2, 1.0, 3.0}) {  // in cell sides
                double worst = 0.0;
                for (int trial = 0; trial < 12; ++trial) {
                    Cell c;
                    c.stepDeg = spacing.stepDeg;
                    c.northDeg = std::min(latitude + unit(random) * c.stepDeg, 89.9);
                    const double side = Wgs84::kEquatorialRadius * c.stepDeg * kRadian;
                    const double base = -400.0 + 8400.0 * unit(random);
                    for (double& h : c.heights) h = base + (2.0 * unit(random) - 1.0) * rise * side;
                    const GeographicCells cells = shapeOf(c);
                    const double error = drawnError(c);
                    const double bound = geographicTriangleErrorBound(cells);
                    worst = std::max(worst, error / bound);
                    ASSERT_LE(error, bound) << spacing.name << " at " << c.northDeg << "°, rise "
                                            << rise << " cell sides";
                    // The sag alone, at the grid's spacing (the native tiles' bound before).
                    const double sagOnly = flatTriangleErrorBound(
                        Wgs84::kMaxCurvatureRadius * c.stepDeg * kRadian, cells.minHeightM);
                    worstOldRatio = std::max(worstOldRatio, error / sagOnly);
                }
                worstRatio = std::max(worstRatio, worst);
            }
        }
    }
    std::cout << "largest error / bound " << worstRatio << ", / the sag alone " << worstOldRatio
              << "\n";
    // Not vacuous: some cell comes within a third of it (the bound takes every triangle
    // the tessellator draws, whose circles are up to 4/3 as wide as a grid triangle's).
    EXPECT_GT(worstRatio, 0.65);
    // And the sag alone was no bound: steep or polar cells stray several times beyond it.
    EXPECT_GT(worstOldRatio, 2.0);
}

TEST(GeographicCellError, WithoutSlopeItIsAboutTheSagAlone) {
    GeographicCells cells;
    cells.lonStepRad = cells.latStepRad = (1.0 / 3.0) * kRadian;
    cells.southRad = -cells.latStepRad;
    cells.northRad = 0.0;
    const double side = Wgs84::kMaxCurvatureRadius * cells.latStepRad;
    const double bound = geographicTriangleErrorBound(cells);
    // A right triangle of legs s fits a circle of radius s/√2: its sag is s²/(4ρ); the bound,
    // for any triangle the tessellator draws, is flatTriangleErrorBound's s²/(3ρ).
    EXPECT_GE(bound, side * side / (4.0 * Wgs84::kMinCurvatureRadius));
    EXPECT_GE(bound, flatTriangleErrorBound(side));
    EXPECT_LE(bound, 1.1 * flatTriangleErrorBound(side));
}

}  // namespace
}  // namespace terrain::globe
