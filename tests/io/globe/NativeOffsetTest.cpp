// Float-safe positions of native tiles (NativeOffset.h; docs/globe.md, "Native leaves")
// against a double-precision reference, as SurfaceOffsetTest holds the face patches: grids as
// fine as SRTM1 and as coarse as ETOPO's 20′, at the equator, across the antimeridian, near
// both poles and at Rainier, from 1 m to 36,000 km. Within 10 km of the camera a vertex must be
// within 1 cm of the reference; anywhere on the tile its error seen from the camera under
// 1e-5 rad.
#include "terrain/globe/NativeOffset.h"
#include "terrain/globe/Wgs84.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>
#include <string>
#include <vector>

namespace terrain::globe {
namespace {

struct Place {
    std::string name;
    double latitudeDeg;
    double longitudeDeg;
};

struct Grid {
    std::string name;
    double pixelDeg;
};

TEST(NativeOffset, CameraRelativeFloatPositionsMatchTheDoubleReference) {
    const std::vector<Place> places{
        {"equator", 0.0, 0.0},
        {"antimeridian east", 0.3, 179.9999},
        {"antimeridian west", -0.3, -179.9999},
        {"near the north pole", 89.7, 37.0},
        {"near the south pole", -89.7, -122.0},
        {"Rainier", 46.8523, -121.7603},
    };
    const std::vector<Grid> grids{
        {"SRTM1", 1.0 / 3600.0}, {"SRTM3", 1.0 / 1200.0}, {"ETOPO 20'", 1.0 / 3.0}};
    std::mt19937_64 random(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    double worstNear = 0.0, worstAngle = 0.0;
    for (const Place& place : places) {
        for (const Grid& g : grids) {
            // A grid whose north-west corner lies a few tiles north-west of the place, no
            // further north than the pole.
            NativeGridGeometry grid;
            grid.pixelLonDeg = grid.pixelLatDeg = g.pixelDeg;
            grid.quads = 128;
            const double tileDeg = g.pixelDeg * grid.quads;
            grid.westDeg = place.longitudeDeg - 2.5 * tileDeg;
            grid.northDeg = std::min(90.0, place.latitudeDeg + 2.5 * tileDeg);
            const auto x = static_cast<std::int64_t>(
                std::floor((place.longitudeDeg - grid.westDeg) / tileDeg));
            const auto y = static_cast<std::int64_t>(
                std::floor((grid.northDeg - place.latitudeDeg) / tileDeg));
            for (const double altitude : {1.0, 100.0, 10e3, 1e6, 20e6, 36e6}) {
                const glm::dvec3 camera =
                    Wgs84::toEcef({place.latitudeDeg, place.longitudeDeg, altitude});
                const glm::dvec2 uv0 = nearestNativeCoordinates(grid, x, y, Wgs84::upAt(camera));
                const NativeSurfaceFrame frame =
                    makeNativeSurfaceFrame(grid, x, y, uv0.x, uv0.y, camera);
                // 10 km in tile coordinates (a tile is about 111 km · tileDeg wide or less).
                const double nearSpan = std::min(1.0, 10e3 / (111e3 * tileDeg));
                for (int k = 0; k < 400; ++k) {
                    const bool nearby = k < 300;
                    const double du =
                        nearby ? (unit(random) * 2.0 - 1.0) * nearSpan : unit(random) - uv0.x;
                    const double dv =
                        nearby ? (unit(random) * 2.0 - 1.0) * nearSpan : unit(random) - uv0.y;
                    const float u = static_cast<float>(std::clamp(uv0.x + du, 0.0, 1.0));
                    const float v = static_cast<float>(std::clamp(uv0.y + dv, 0.0, 1.0));
                    const float height = static_cast<float>(-500.0 + 9500.0 * unit(random));
                    const glm::dvec2 lonLat = grid.lonLatDeg(x, y, u, v);
                    if (std::abs(lonLat.y) > 90.0) continue;
                    const glm::dvec3 truth =
                        Wgs84::pointAlongNormal(Wgs84::normalAt(lonLat.y, lonLat.x), height) -
                        camera;
                    glm::vec3 up;
                    const glm::dvec3 drawn =
                        glm::dvec3(nativeCameraRelativePosition(frame, u, v, height, &up));
                    const double error = glm::distance(drawn, truth);
                    const double distance = glm::length(truth);
                    const std::string where =
                        place.name + ", " + g.name + ", " + std::to_string(altitude) + " m";
                    ASSERT_LT(glm::distance(glm::dvec3(up), Wgs84::normalAt(lonLat.y, lonLat.x)),
                              1e-6)
                        << where;
                    if (distance <= 10e3) {
                        ASSERT_LT(error, 0.01) << where << ", " << distance << " m away";
                        worstNear = std::max(worstNear, error);
                    }
                    ASSERT_LT(error, 1e-5 * distance + 1e-3)
                        << where << ", " << distance << " m away";
                    if (distance > 1.0) worstAngle = std::max(worstAngle, error / distance);
                }
            }
        }
    }
    std::cout << "within 10 km: worst " << worstNear * 1000.0 << " mm; worst angle anywhere "
              << worstAngle << " rad\n";
}

TEST(NativeOffset, NearestCoordinatesFindTheNadirAcrossTheAntimeridian) {
    NativeGridGeometry grid;
    grid.westDeg = 179.5;
    grid.northDeg = 1.0;
    grid.pixelLonDeg = grid.pixelLatDeg = 1.0 / 1200.0;
    grid.quads = 128;
    // The camera at −179.95°, 0.5° N is 0.55° east of the grid's west edge and 0.5° south of
    // its north edge: tile (5, 4) (0.107° wide).
    const glm::dvec3 camera = Wgs84::toEcef({0.5, -179.95, 2000.0});
    const glm::dvec2 uv = nearestNativeCoordinates(grid, 5, 4, Wgs84::upAt(camera));
    const glm::dvec2 lonLat = grid.lonLatDeg(5, 4, uv.x, uv.y);
    EXPECT_NEAR(lonLat.x - 360.0, -179.95, 1e-9);
    EXPECT_NEAR(lonLat.y, 0.5, 1e-9);
}

}  // namespace
}  // namespace terrain::globe
