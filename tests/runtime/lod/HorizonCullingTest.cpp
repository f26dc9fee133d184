// Horizon culling (Cesium's ellipsoidal occluder) never removes a visible point: every patch
// it culls, from cameras at 1 m to 36,000 km over random places, has all its sampled surface
// points behind the occluding ellipsoid (a segment-ellipsoid test in double). It removes most
// of the globe from low orbit, and refuses boxes it cannot summarise.
#include "terrain/runtime/HorizonCulling.h"

#include "terrain/globe/Wgs84.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <iostream>
#include <random>

namespace terrain::runtime {
namespace {

using globe::GlobePatchId;
using globe::Wgs84;

/// True when the segment from `camera` to `point` passes through the occluder's interior.
bool segmentHitsOccluder(const EllipsoidalOccluder& occluder, const glm::dvec3& camera,
                         const glm::dvec3& point) {
    const glm::dvec3 c = occluder.toScaledSpace(camera);
    const glm::dvec3 p = occluder.toScaledSpace(point);
    const glm::dvec3 d = p - c;
    // |c + t·d|² < 1 for some t in (0, 1): the quadratic's minimum over the segment.
    const double t = std::clamp(-glm::dot(c, d) / glm::dot(d, d), 0.0, 1.0);
    const glm::dvec3 closest = c + t * d;
    return glm::dot(closest, closest) < 1.0 - 1e-12;
}

TEST(HorizonCulling, NeverCullsAVisiblePoint) {
    std::mt19937_64 random(5);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    int culled = 0;
    int tested = 0;
    for (const double shrink : {0.0, 11000.0}) {
        EllipsoidalOccluder occluder(shrink);
        for (int trial = 0; trial < 300; ++trial) {
            const double latitude = std::asin(2.0 * unit(random) - 1.0) * 180.0 / M_PI;
            const double longitude = 360.0 * unit(random) - 180.0;
            const double altitude = std::pow(10.0, 7.6 * unit(random));  // 1 m to 36,000 km
            const glm::dvec3 camera = Wgs84::toEcef({latitude, longitude, altitude});
            occluder.setCamera(camera);
            for (int p = 0; p < 40; ++p) {
                const int level = 1 + static_cast<int>(unit(random) * 9);
                const std::int64_t n = globe::patchesPerFaceSide(level);
                const auto index = [&] {
                    return static_cast<std::int64_t>(unit(random) * static_cast<double>(n));
                };
                const int face = static_cast<int>(unit(random) * 6);
                const std::int64_t x = index();
                const GlobePatchId id{face, level, x, index()};
                const double minHeight = -shrink * unit(random);
                const double maxHeight = minHeight + 9000.0 * unit(random);
                const auto box = globe::patchBounds(id, minHeight, maxHeight);
                ++tested;
                if (!occluder.isHidden(box)) continue;
                ++culled;
                for (int k = 0; k < 64; ++k) {
                    const globe::FacePoint fp = globe::patchPoint(id, (k % 8) / 7.0, (k / 8) / 7.0);
                    const double height = minHeight + (maxHeight - minHeight) * unit(random);
                    const glm::dvec3 point =
                        Wgs84::pointAlongNormal(globe::directionOf(fp.face, fp.s, fp.t), height);
                    ASSERT_TRUE(segmentHitsOccluder(occluder, camera, point))
                        << "culled a visible point: camera " << latitude << ", " << longitude
                        << ", " << altitude << " m; patch face " << id.face << " level " << level;
                }
            }
        }
    }
    std::cout << "horizon culling removed " << culled << " of " << tested << " random patches\n";
    EXPECT_GT(culled, tested / 10);
}

TEST(HorizonCulling, RemovesMostOfTheGlobeFromLowOrbit) {
    EllipsoidalOccluder occluder;
    occluder.setCamera(Wgs84::toEcef({20.0, 30.0, 1000e3}));
    int culled = 0;
    int total = 0;
    constexpr int kLevel = 4;
    for (int face = 0; face < globe::kCubeFaces; ++face) {
        for (std::int64_t y = 0; y < 16; ++y) {
            for (std::int64_t x = 0; x < 16; ++x) {
                ++total;
                culled += occluder.isHidden(globe::patchBounds({face, kLevel, x, y}, 0.0, 0.0));
            }
        }
    }
    std::cout << "from 1,000 km, horizon culling removes " << culled << " of " << total << " level-"
              << kLevel << " patches\n";
    // The visible cap from 1,000 km is about 7 % of the sphere.
    EXPECT_GT(culled, total * 8 / 10);
}

TEST(HorizonCulling, NeverCullsWhatItCannotSummarise) {
    EllipsoidalOccluder occluder;
    occluder.setCamera(Wgs84::toEcef({0.0, 0.0, 500e3}));
    // A box around the far half of the planet: corners on both sides of its centre's horizon.
    globe::OrientedBox huge;
    huge.centre = Wgs84::toEcef({0.0, 180.0, 0.0}) * 0.5;
    huge.axes = {glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1), glm::dvec3(-1, 0, 0)};
    huge.halfExtents = glm::dvec3(7e6, 7e6, 4e6);
    const auto corners = huge.corners();
    EXPECT_FALSE(occluder.horizonCullingPoint(huge.centre, corners).has_value());
    EXPECT_FALSE(occluder.isHidden(huge));
    // The camera below the occluder (a trench deeper than the shrink): only what is behind the
    // plane through it is culled, and nothing crashes.
    occluder.setCamera(Wgs84::toEcef({0.0, 0.0, -8000.0}));
    EXPECT_FALSE(occluder.isHidden(globe::patchBounds({0, 8, 128, 128}, -9000.0, -7000.0)));
}

}  // namespace
}  // namespace terrain::runtime
