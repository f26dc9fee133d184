// The globe viewer's controls without a window: dragging moves the ground with the cursor
// (as far as the pixels cover at that height), the wheel zooms toward the cursor's ground
// point, flight speed follows the height, the camera never goes below its floor, and the
// poles and the antimeridian are crossed without a jump.
#include "terrain/runtime/GlobeController.h"

#include <gtest/gtest.h>

#include <cmath>

namespace terrain::runtime {
namespace {

TEST(GlobeController, DraggingMovesTheGroundWithTheCursor) {
    GlobeController controller;
    GlobePose pose{{10.0, 20.0, 10000.0}, 0.0, -90.0};
    GlobeControlInput input;
    input.focalPx = 1000.0;
    input.held.lookDyPx = 100.0;  // drag down: the ground comes toward the camera's back
    controller.update(pose, input, 0.0, 0.0);
    // 100 px of 10 m each (10 km high, 1000 px focal length): 1 km north.
    EXPECT_NEAR((pose.where.latitudeDeg - 10.0) * globe::Wgs84::kEquatorialRadius * M_PI / 180.0,
                1000.0, 1.0);
    EXPECT_DOUBLE_EQ(pose.where.longitudeDeg, 20.0);
    EXPECT_DOUBLE_EQ(pose.where.height, 10000.0);
}

TEST(GlobeController, WheelZoomsTowardTheCursorAndSpeedFollowsHeight) {
    GlobeController controller;
    GlobePose pose{{0.0, 0.0, 1e6}, 0.0, -90.0};
    GlobeControlInput input;
    input.held.wheelSteps = 1.0;
    input.zoomToward = globe::Geodetic{2.0, 4.0, 0.0};
    controller.update(pose, input, 0.0, 0.0);
    EXPECT_NEAR(pose.where.height, 0.85e6, 1e-6);
    EXPECT_NEAR(pose.where.latitudeDeg, 0.3, 1e-12);
    EXPECT_NEAR(pose.where.longitudeDeg, 0.6, 1e-12);

    // One second forward moves one height (clamped between the speed limits).
    for (const double height : {100.0, 50e3}) {
        GlobePose fly{{0.0, 0.0, height}, 90.0, -10.0};
        GlobeControlInput keys;
        keys.held.forward = true;
        controller.update(fly, keys, 1.0, 0.0);
        const double eastM =
            fly.where.longitudeDeg * M_PI / 180.0 * globe::Wgs84::kEquatorialRadius;
        EXPECT_NEAR(eastM, height, 1e-6 * height);
    }
}

TEST(GlobeController, NeverBelowTheFloorAndCrossesTheAntimeridian) {
    GlobeController controller;
    GlobePose pose{{0.0, 179.99, 500.0}, 90.0, -10.0};
    GlobeControlInput input;
    input.held.down = true;
    for (int i = 0; i < 100; ++i) controller.update(pose, input, 0.1, 450.0);
    EXPECT_GE(pose.where.height, 451.0 - 1e-9);
    input.held.down = false;
    input.held.forward = true;
    GlobePose east{{0.0, 179.99, 20e3}, 90.0, -10.0};
    controller.update(east, input, 1.0, 0.0);    // 20 km east, over the antimeridian
    EXPECT_LT(east.where.longitudeDeg, -179.0);  // east of 180° is −180° + …
    // Flying north over the pole stops just short of it rather than flipping.
    GlobePose polar{{89.99, 0.0, 5000.0}, 0.0, -30.0};
    controller.update(polar, input, 10.0, 0.0);
    EXPECT_LE(polar.where.latitudeDeg, 90.0);
    EXPECT_GT(polar.where.latitudeDeg, 89.99);
}

TEST(GlobeController, GoesToTheDataAndToTheWholeEarth) {
    const GlobePose rainier = GlobeController::overExtent(-122.0, 46.0, -121.0, 47.0, 1.0);
    EXPECT_NEAR(rainier.where.latitudeDeg, 46.5, 1e-12);
    EXPECT_NEAR(rainier.where.longitudeDeg, -121.5, 1e-12);
    EXPECT_GT(rainier.where.height, 50e3);
    EXPECT_LT(rainier.where.height, 300e3);
    const GlobePose across = GlobeController::overExtent(179.0, -10.0, -179.0, 10.0, 1.0);
    EXPECT_NEAR(std::abs(across.where.longitudeDeg), 180.0, 1e-9);
    EXPECT_DOUBLE_EQ(GlobeController::wholeEarth(10.0, 20.0).where.height, 20e6);
}

}  // namespace
}  // namespace terrain::runtime
