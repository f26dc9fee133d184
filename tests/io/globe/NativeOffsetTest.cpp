// Float-safe positions of native tiles (NativeOffset.h; docs/globe.md, "Native leaves")
// against a double-precision reference, as SurfaceOffsetTest holds the face patches: grids as
// fine as SRTM1 and as coarse as ETOPO's 20′, at the equator, across the antimeridian, near
// both poles and at Rainier, from 1 m to 36,000 km. Within 10 km of the camera a vertex must be
// within 1 cm of the reference; anywhere on the tile its error seen from the camera under
// 1e-5 rad. Their imagery coordinates on a face patch, likewise float against double: within
// 1 cm of the ground near the camera.
#include "terrain/globe/CubeSphere.h"
#include "terrain/globe/NativeOffset.h"
#include "terrain/globe/Wgs84.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <numbers>
#include <optional>
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

// A grid of `g`'s spacing whose north-west corner lies a few tiles north-west of `place`, no
// further north than the pole, and its tile (x, y) holding the place.
struct GridAround {
    NativeGridGeometry grid;
    std::int64_t x = 0;
    std::int64_t y = 0;
    double tileDeg = 0.0;
};

GridAround gridAround(const Place& place, const Grid& g) {
    GridAround around;
    NativeGridGeometry& grid = around.grid;
    grid.pixelLonDeg = grid.pixelLatDeg = g.pixelDeg;
    grid.quads = 128;
    around.tileDeg = g.pixelDeg * grid.quads;
    grid.westDeg = place.longitudeDeg - 2.5 * around.tileDeg;
    grid.northDeg = std::min(90.0, place.latitudeDeg + 2.5 * around.tileDeg);
    around.x =
        static_cast<std::int64_t>(std::floor((place.longitudeDeg - grid.westDeg) / around.tileDeg));
    around.y =
        static_cast<std::int64_t>(std::floor((grid.northDeg - place.latitudeDeg) / around.tileDeg));
    return around;
}

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
            const auto [grid, x, y, tileDeg] = gridAround(place, g);
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

// A native tile's vertices' (u, v) on the face patch whose imagery they drape (surface_globe.glsl,
// nativeImageryUv; its twin nativeImageryCoordinates) against the double-precision patch
// coordinates of their direction: the patch is the level-12 one (2.4 km) under the place, the
// points within 10 km of it, on a grid from SRTM1 to ETOPO's 20', at the places above and on
// a cube edge. Within 1 cm on the ground, and no further off than 1e-6 of a face (6 m) on the
// whole tile where it lies over the face.
TEST(NativeOffset, ImageryCoordinatesOnAFacePatchMatchTheDoubleReference) {
    const std::vector<Place> places{
        {"equator", 0.0, 0.0},
        {"antimeridian east", 0.3, 179.9999},
        {"near the north pole", 89.7, 37.0},
        {"Rainier", 46.8523, -121.7603},
        {"a cube edge", 10.0, 45.0001},
    };
    const std::vector<Grid> grids{
        {"SRTM1", 1.0 / 3600.0}, {"SRTM3", 1.0 / 1200.0}, {"ETOPO 20'", 1.0 / 3.0}};
    constexpr int kLevel = 12;
    // Metres per unit of u on the ground, at most (the face's spacing varies within √2).
    const double metresPerU = 0.5 * std::numbers::pi * Wgs84::kEquatorialRadius /
                              double(patchesPerFaceSide(kLevel)) * std::sqrt(2.0);
    std::mt19937_64 random(11);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    double worstNear = 0.0;
    int compared = 0;
    for (const Place& place : places) {
        for (const Grid& g : grids) {
            const auto [grid, x, y, tileDeg] = gridAround(place, g);
            const FacePoint at =
                facePointOf(Wgs84::normalAt(place.latitudeDeg, place.longitudeDeg));
            const double n = double(patchesPerFaceSide(kLevel));
            const GlobePatchId patch{at.face, kLevel,
                                     static_cast<std::int64_t>(std::floor(at.s * n)),
                                     static_cast<std::int64_t>(std::floor(at.t * n))};
            const glm::dvec3 camera = Wgs84::toEcef({place.latitudeDeg, place.longitudeDeg, 300.0});
            const glm::dvec2 uv0 = nearestNativeCoordinates(grid, x, y, Wgs84::upAt(camera));
            const NativeSurfaceFrame frame =
                makeNativeSurfaceFrame(grid, x, y, uv0.x, uv0.y, camera);
            const NativeImageryFrame imagery = makeNativeImageryFrame(grid, x, y, frame, patch);
            const double nearSpan = std::min(1.0, 10e3 / (111e3 * tileDeg));
            for (int k = 0; k < 400; ++k) {
                const bool nearby = k < 300;
                const double du =
                    nearby ? (unit(random) * 2.0 - 1.0) * nearSpan : unit(random) - uv0.x;
                const double dv =
                    nearby ? (unit(random) * 2.0 - 1.0) * nearSpan : unit(random) - uv0.y;
                const float u = static_cast<float>(std::clamp(uv0.x + du, 0.0, 1.0));
                const float v = static_cast<float>(std::clamp(uv0.y + dv, 0.0, 1.0));
                const glm::dvec2 lonLat = grid.lonLatDeg(x, y, u, v);
                if (std::abs(lonLat.y) > 90.0) continue;
                const std::optional<glm::dvec2> truth =
                    patchCoordinatesOf(patch, Wgs84::normalAt(lonLat.y, lonLat.x));
                if (!truth) continue;  // off the face's side of the globe: no imagery drawn
                const glm::dvec2 drawn(nativeImageryCoordinates(imagery, frame.direction0,
                                                                nativeDeltaDirection(frame, u, v)));
                const double errorM = glm::distance(drawn, *truth) * metresPerU;
                const double distance = glm::distance(
                    Wgs84::pointAlongNormal(Wgs84::normalAt(lonLat.y, lonLat.x), 0.0), camera);
                const std::string where = place.name + ", " + g.name;
                ASSERT_LT(glm::distance(drawn, *truth) / n, 1e-6) << where;
                if (distance <= 10e3) {
                    ASSERT_LT(errorM, 0.01) << where << ", " << distance << " m away";
                    worstNear = std::max(worstNear, errorM);
                }
                ++compared;
            }
        }
    }
    EXPECT_GT(compared, 4000);
    std::cout << "imagery coordinates within 10 km: worst " << worstNear * 1000.0 << " mm\n";
}

// A native tile's outline on a face patch: the box holds the tile's corners; a tile across a
// cube edge reaches past the face (u beyond its patches); one beyond 60° has none.
TEST(NativeOffset, TheOutlineOfANativeTileOnAFacePatch) {
    NativeGridGeometry grid;
    grid.westDeg = 44.9;
    grid.northDeg = 0.2;
    grid.pixelLonDeg = grid.pixelLatDeg = 1.0 / 1200.0;  // tiles 0.107° wide
    grid.quads = 128;
    // Face 0 (+X) ends at 45° E; tile (0, 0) spans 44.9° … 45.007° E.
    const GlobePatchId patch{0, 8, 255, 127};  // the face's east column, at the equator
    const std::optional<glm::dvec4> box = nativeTileExtentOn(grid, 0, 0, patch);
    ASSERT_TRUE(box.has_value());
    for (const glm::dvec2 corner :
         {glm::dvec2(0, 0), glm::dvec2(1, 0), glm::dvec2(0, 1), glm::dvec2(1, 1)}) {
        const glm::dvec2 lonLat = grid.lonLatDeg(0, 0, corner.x, corner.y);
        const glm::dvec2 uv =
            patchCoordinatesOf(patch, Wgs84::normalAt(lonLat.y, lonLat.x)).value();
        EXPECT_GE(uv.x, box->x - 1e-12);
        EXPECT_LE(uv.x, box->z + 1e-12);
        EXPECT_GE(uv.y, box->y - 1e-12);
        EXPECT_LE(uv.y, box->w + 1e-12);
    }
    EXPECT_GT(box->z, 1.0);  // past the face's east edge
    NativeGridGeometry far = grid;
    far.westDeg = 100.0;  // 100° E: 100° from face 0's normal
    EXPECT_FALSE(nativeTileExtentOn(far, 0, 0, patch).has_value());
}

}  // namespace
}  // namespace terrain::globe
