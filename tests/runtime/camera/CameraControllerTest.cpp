// CameraController driven by synthetic input, no window: motion does not depend on how time
// is split into frames, fly speed follows the height above the ground, the floor holds,
// mouse-look and the wheel, orbiting keeps the pivot centred, jumps land where asked, and
// screen picking inverts the projection.
#include "terrain/runtime/CameraController.h"

#include "terrain/runtime/Camera.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

#include <cmath>
#include <numbers>

namespace terrain::runtime {
namespace {

constexpr double kPi = std::numbers::pi;

double rad(double degrees) { return degrees * kPi / 180.0; }

// Rolling ground: flat enough to fly over, uneven enough that the speed changes on the way.
double rollingGround(double x, double y) {
    return 100.0 + 40.0 * std::sin(x / 700.0) + 25.0 * std::cos(y / 450.0);
}

GroundHeightFn flatGround(double z) {
    return [z](double, double) { return z; };
}

Camera startCamera() {
    Camera camera;
    camera.position = {1000.0, 2000.0, 400.0};
    camera.yaw = rad(30.0);
    camera.pitch = rad(-10.0);
    camera.viewportWidth = 800;
    camera.viewportHeight = 600;
    camera.fovY = rad(60.0);
    return camera;
}

// Runs `frames` frames of `dtS` with the same held input; returns the camera.
Camera fly(const CameraInput& input, int frames, double dtS,
           const GroundHeightFn& ground = rollingGround, Camera camera = startCamera(),
           CameraControllerOptions options = {}) {
    CameraController controller(options);
    for (int i = 0; i < frames; ++i) controller.update(camera, input, dtS, ground);
    return camera;
}

double angleBetween(const glm::dvec3& a, const glm::dvec3& b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

TEST(CameraController, FlightIsFrameRateIndependent) {
    CameraInput input;
    input.forward = true;
    input.up = true;  // climbing: the speed grows with the height during the second
    input.right = true;
    input.boost = true;
    const Camera start = startCamera();
    const Camera at60 = fly(input, 60, 1.0 / 60.0);
    const Camera at10 = fly(input, 10, 1.0 / 10.0);
    const Camera at7 = fly(input, 7, 1.0 / 7.0);  // sub-steps of another length
    const Camera at144 = fly(input, 144, 1.0 / 144.0);
    const double travelled = glm::length(at60.position - start.position);
    ASSERT_GT(travelled, 1000.0);  // it did fly (boosted, from 300 m above the ground)
    EXPECT_LT(glm::length(at10.position - at60.position), 1e-6 * travelled);
    EXPECT_LT(glm::length(at7.position - at60.position), 0.01 * travelled);
    EXPECT_LT(glm::length(at144.position - at60.position), 0.01 * travelled);
}

TEST(CameraController, ReleasedKeysStopTheCameraFrameRateIndependently) {
    // Half a second forward, then a second coasting to a stop.
    struct Result {
        Camera camera;
        double heldSpeed = 0.0;
        double finalSpeed = 0.0;
    };
    const auto run = [](int framesPerHalfSecond) {
        Result r;
        r.camera = startCamera();
        CameraController controller;
        CameraInput held;
        held.forward = true;
        const double dt = 0.5 / framesPerHalfSecond;
        for (int i = 0; i < framesPerHalfSecond; ++i) {
            controller.update(r.camera, held, dt, rollingGround);
        }
        r.heldSpeed = glm::length(controller.velocity());
        for (int i = 0; i < 2 * framesPerHalfSecond; ++i) {
            controller.update(r.camera, {}, dt, rollingGround);
        }
        r.finalSpeed = glm::length(controller.velocity());
        return r;
    };
    const Result fast = run(30);
    const Result slow = run(5);
    const double travelled = glm::length(fast.camera.position - startCamera().position);
    ASSERT_GT(travelled, 50.0);
    EXPECT_LT(glm::length(slow.camera.position - fast.camera.position), 0.01 * travelled);
    // τ = 0.1 s: a second after the keys are released the camera has stopped (e^−10).
    EXPECT_GT(fast.heldSpeed, 100.0);
    EXPECT_LT(fast.finalSpeed, 1e-3 * fast.heldSpeed);
    EXPECT_NEAR(slow.heldSpeed, fast.heldSpeed, 0.01 * fast.heldSpeed);
}

TEST(CameraController, SpeedScalesWithHeightAboveGround) {
    CameraInput input;
    input.forward = true;
    CameraControllerOptions options;
    options.responseS = 0.0;  // full speed at once: the distance is speed × time
    Camera low = startCamera();
    low.pitch = 0.0;
    low.position.z = 100.0;
    Camera high = low;
    high.position.z = 1000.0;
    const double seconds = 0.5;
    const Camera lowEnd = fly(input, 30, seconds / 30, flatGround(0.0), low, options);
    const Camera highEnd = fly(input, 30, seconds / 30, flatGround(0.0), high, options);
    EXPECT_NEAR(glm::length(lowEnd.position - low.position), 100.0 * seconds, 1e-6);
    EXPECT_NEAR(glm::length(highEnd.position - high.position), 1000.0 * seconds, 1e-6);

    // Height above the ground, not above zero: the same flight over a 900 m plateau is slow.
    const Camera plateauEnd = fly(input, 30, seconds / 30, flatGround(900.0), high, options);
    EXPECT_NEAR(glm::length(plateauEnd.position - high.position), 100.0 * seconds, 1e-6);

    // Near the ground the speed stays at the minimum rather than going to zero.
    Camera grazing = low;
    grazing.position.z = 2.5;
    const Camera grazingEnd = fly(input, 30, seconds / 30, flatGround(0.0), grazing, options);
    EXPECT_NEAR(glm::length(grazingEnd.position - grazing.position), options.minSpeedMps * seconds,
                1e-6);
}

TEST(CameraController, BoostSlowAndWheelScaleTheSpeed) {
    CameraControllerOptions options;
    options.responseS = 0.0;
    Camera camera = startCamera();
    camera.pitch = 0.0;
    camera.position.z = 200.0;
    const auto distance = [&](CameraInput input, double wheelSteps = 0.0) {
        CameraController controller(options);
        Camera c = camera;
        CameraInput first = input;
        first.wheelSteps = wheelSteps;
        controller.update(c, first, 0.0, flatGround(0.0));  // the wheel alone, no time
        controller.update(c, input, 0.25, flatGround(0.0));
        return glm::length(c.position - camera.position);
    };
    CameraInput forward;
    forward.forward = true;
    const double plain = distance(forward);
    EXPECT_NEAR(plain, 200.0 * 0.25, 1e-6);
    CameraInput boosted = forward;
    boosted.boost = true;
    EXPECT_NEAR(distance(boosted), plain * options.boostFactor, 1e-6);
    CameraInput slowed = forward;
    slowed.slow = true;
    EXPECT_NEAR(distance(slowed), plain * options.slowFactor, 1e-6);
    EXPECT_NEAR(distance(forward, 2.0), plain * options.wheelSpeedStep * options.wheelSpeedStep,
                1e-6);
    EXPECT_NEAR(distance(forward, -1.0), plain / options.wheelSpeedStep, 1e-6);
}

TEST(CameraController, MovesAlongTheViewAndTheWorldVertical) {
    CameraControllerOptions options;
    options.responseS = 0.0;
    const Camera start = startCamera();
    CameraInput forward;
    forward.forward = true;
    const Camera ahead = fly(forward, 10, 0.01, rollingGround, start, options);
    EXPECT_LT(angleBetween(ahead.position - start.position, start.forward()), 1e-9);
    CameraInput left;
    left.left = true;
    const Camera leftEnd = fly(left, 10, 0.01, rollingGround, start, options);
    EXPECT_LT(angleBetween(leftEnd.position - start.position, -start.right()), 1e-9);
    CameraInput up;
    up.up = true;
    const Camera upEnd = fly(up, 10, 0.01, rollingGround, start, options);
    EXPECT_LT(angleBetween(upEnd.position - start.position, {0.0, 0.0, 1.0}), 1e-9);
    // Opposite keys cancel.
    CameraInput both;
    both.forward = both.back = true;
    EXPECT_EQ(fly(both, 10, 0.01, rollingGround, start, options).position, start.position);
}

TEST(CameraController, MouseLookTurnsByTravelNotByFrames) {
    CameraController controller;
    const double perPx = controller.options().lookRadiansPerPx;
    Camera once = startCamera();
    CameraInput move;
    move.lookDxPx = 120.0;
    move.lookDyPx = 40.0;  // mouse down: look down
    controller.update(once, move, 1.0 / 60.0, rollingGround);
    EXPECT_NEAR(once.yaw, rad(30.0) + 120.0 * perPx, 1e-12);
    EXPECT_NEAR(once.pitch, rad(-10.0) - 40.0 * perPx, 1e-12);

    Camera split = startCamera();
    CameraInput piece;
    piece.lookDxPx = 12.0;
    piece.lookDyPx = 4.0;
    CameraController other;
    for (int i = 0; i < 10; ++i) other.update(split, piece, 1.0 / 600.0, rollingGround);
    EXPECT_NEAR(split.yaw, once.yaw, 1e-12);
    EXPECT_NEAR(split.pitch, once.pitch, 1e-12);

    // Pitch stops short of straight up and down; yaw wraps into [−π, π].
    CameraInput far;
    far.lookDyPx = -1e6;
    far.lookDxPx = 2.5 * kPi / perPx;
    controller.update(once, far, 0.0, rollingGround);
    EXPECT_DOUBLE_EQ(once.pitch, Camera::kMaxPitch);
    EXPECT_GE(once.yaw, -kPi);
    EXPECT_LE(once.yaw, kPi);
    EXPECT_NEAR(std::remainder(once.yaw - (rad(30.0) + 120.0 * perPx + 2.5 * kPi), 2.0 * kPi), 0.0,
                1e-9);
}

TEST(CameraController, FloorKeepsTheCameraAboveTheGround) {
    CameraInput dive;
    dive.down = true;
    dive.forward = true;
    dive.boost = true;
    Camera camera = startCamera();
    camera.pitch = rad(-60.0);
    CameraController controller;
    for (int i = 0; i < 600; ++i) {
        controller.update(camera, dive, 1.0 / 60.0, rollingGround);
        const double floor =
            rollingGround(camera.position.x, camera.position.y) + controller.options().clearanceM;
        ASSERT_GE(camera.position.z, floor - 1e-9) << "frame " << i;
    }
    EXPECT_NEAR(controller.heightAboveGroundM(), controller.options().clearanceM, 1e-9);

    // Without the floor the same dive goes below the ground.
    CameraControllerOptions free;
    free.keepAboveGround = false;
    Camera through = startCamera();
    through.pitch = rad(-60.0);
    const Camera end = fly(dive, 600, 1.0 / 60.0, rollingGround, through, free);
    EXPECT_LT(end.position.z, rollingGround(end.position.x, end.position.y));
}

TEST(CameraController, LongFramesAreCappedSoHitchesDoNotThrowTheCamera) {
    CameraInput input;
    input.forward = true;
    const Camera start = startCamera();
    const Camera hitch = fly(input, 1, 5.0);
    const Camera capped = fly(input, 1, CameraControllerOptions{}.maxFrameS);
    EXPECT_EQ(hitch.position, capped.position);
    EXPECT_NE(hitch.position, start.position);
}

TEST(CameraController, OrbitKeepsThePivotCentredAndTheDistance) {
    Camera camera = startCamera();
    const glm::dvec3 pivot{1500.0, 2600.0, 120.0};
    CameraController controller;
    controller.orbit(camera, pivot);
    EXPECT_EQ(controller.mode(), CameraMode::Orbit);
    const double distance = glm::length(camera.position - pivot);
    EXPECT_NEAR(controller.orbitDistance(), distance, 1e-9);
    EXPECT_LT(angleBetween(camera.forward(), pivot - camera.position), 1e-9);

    // Drag round a full turn in uneven pieces: always looking at the pivot from the same
    // distance, and back where it started.
    const glm::dvec3 startPosition = camera.position;
    const double perPx = controller.options().lookRadiansPerPx;
    const double fullTurnPx = 2.0 * kPi / perPx;
    const double pieces[] = {0.1, 0.25, 0.05, 0.3, 0.3};
    for (double piece : pieces) {
        CameraInput drag;
        drag.lookDxPx = piece * fullTurnPx;
        controller.update(camera, drag, 1.0 / 60.0, flatGround(0.0));
        EXPECT_LT(angleBetween(camera.forward(), pivot - camera.position), 1e-9);
        EXPECT_NEAR(glm::length(camera.position - pivot), distance, 1e-6);
    }
    EXPECT_LT(glm::length(camera.position - startPosition), 1e-6 * distance);

    // Dragging up and down changes the elevation, never past the top or below the pivot.
    CameraInput over;
    over.lookDyPx = 1e6;
    controller.update(camera, over, 0.0, flatGround(0.0));
    EXPECT_DOUBLE_EQ(camera.pitch, -Camera::kMaxPitch);
    CameraInput under;
    under.lookDyPx = -1e6;
    controller.update(camera, under, 0.0, flatGround(0.0));
    EXPECT_DOUBLE_EQ(camera.pitch, -controller.options().orbitMinElevation);
    EXPECT_GT(camera.position.z, pivot.z);
}

TEST(CameraController, OrbitZoomAndPanAreFrameRateIndependent) {
    const glm::dvec3 pivot{1500.0, 2600.0, 120.0};
    const auto run = [&](CameraInput input, int frames, double dt) {
        Camera camera = startCamera();
        CameraController controller;
        controller.orbit(camera, pivot);
        for (int i = 0; i < frames; ++i) controller.update(camera, input, dt, flatGround(0.0));
        return std::make_pair(camera, controller);
    };
    CameraInput zoomOut;
    zoomOut.up = true;
    const auto [cam60, ctl60] = run(zoomOut, 60, 1.0 / 60.0);
    const auto [cam7, ctl7] = run(zoomOut, 7, 1.0 / 7.0);
    Camera reference = startCamera();
    const double d0 = glm::length(reference.position - pivot);
    EXPECT_NEAR(ctl60.orbitDistance(), d0 * std::exp(ctl60.options().orbitZoomPerS), 1e-6 * d0);
    EXPECT_NEAR(ctl7.orbitDistance(), ctl60.orbitDistance(), 1e-6 * d0);
    EXPECT_LT(glm::length(cam7.position - cam60.position), 1e-6 * d0);

    CameraInput pan;
    pan.forward = true;
    pan.right = true;
    const auto [pan60, panCtl60] = run(pan, 60, 1.0 / 60.0);
    const auto [pan10, panCtl10] = run(pan, 10, 1.0 / 10.0);
    const double moved = glm::length(panCtl60.pivot() - pivot);
    EXPECT_NEAR(moved, d0 * panCtl60.options().orbitPanPerS, 1e-6 * d0);
    EXPECT_EQ(panCtl60.pivot().z, pivot.z);  // panning is horizontal
    EXPECT_LT(glm::length(panCtl10.pivot() - panCtl60.pivot()), 1e-6 * d0);
    EXPECT_LT(angleBetween(pan60.forward(), panCtl60.pivot() - pan60.position), 1e-9);

    // The wheel zooms by steps, towards the pivot for positive steps.
    Camera camera = startCamera();
    CameraController controller;
    controller.orbit(camera, pivot);
    CameraInput wheel;
    wheel.wheelSteps = 2.0;
    controller.update(camera, wheel, 0.0, flatGround(0.0));
    const double step = controller.options().wheelZoomStep;
    EXPECT_NEAR(controller.orbitDistance(), d0 * step * step, 1e-6 * d0);
}

TEST(CameraController, OrbitStaysAboveTheGroundAndStillLooksAtThePivot) {
    Camera camera = startCamera();
    const glm::dvec3 pivot{1500.0, 2600.0, 120.0};
    CameraController controller;
    controller.orbit(camera, pivot);
    // A ridge 800 m high everywhere but at the pivot: a low orbit would be inside it.
    const GroundHeightFn ridge = [&](double x, double y) {
        return std::hypot(x - pivot.x, y - pivot.y) < 50.0 ? 0.0 : 800.0;
    };
    CameraInput low;
    low.lookDyPx = -1e6;  // down to the lowest elevation
    controller.update(camera, low, 1.0 / 60.0, ridge);
    EXPECT_GE(camera.position.z, 800.0 + controller.options().clearanceM - 1e-9);
    EXPECT_LT(angleBetween(camera.forward(), pivot - camera.position), 1e-9);
    EXPECT_NEAR(controller.orbitDistance(), glm::length(camera.position - pivot), 1e-6);
}

TEST(CameraController, JumpToPutsTheCameraOverThePoint) {
    Camera camera = startCamera();
    CameraController controller;
    CameraInput forward;
    forward.forward = true;
    controller.update(camera, forward, 0.5, rollingGround);  // moving when it jumps
    const double yaw = camera.yaw;
    controller.jumpTo(camera, 523456.5, 5210987.25, 300.0, rollingGround);
    EXPECT_EQ(camera.position.x, 523456.5);
    EXPECT_EQ(camera.position.y, 5210987.25);
    EXPECT_DOUBLE_EQ(camera.position.z, rollingGround(523456.5, 5210987.25) + 300.0);
    EXPECT_DOUBLE_EQ(camera.pitch, controller.options().jumpPitch);
    EXPECT_LT(camera.pitch, 0.0);  // looking down and ahead
    EXPECT_DOUBLE_EQ(camera.yaw, yaw);
    EXPECT_EQ(controller.velocity(), glm::dvec3(0.0));
    // The motion stopped: a frame without keys leaves the camera where it landed.
    const glm::dvec3 landed = camera.position;
    controller.update(camera, {}, 1.0 / 60.0, rollingGround);
    EXPECT_EQ(camera.position, landed);

    // A height below the clearance still keeps the camera above the ground.
    controller.jumpTo(camera, 10.0, 20.0, 0.0, rollingGround);
    EXPECT_DOUBLE_EQ(camera.position.z,
                     rollingGround(10.0, 20.0) + controller.options().clearanceM);
}

TEST(CameraController, JumpInOrbitModeOrbitsThePoint) {
    Camera camera = startCamera();
    CameraController controller;
    controller.orbit(camera, {1500.0, 2600.0, 120.0});
    controller.jumpTo(camera, 8000.0, -3000.0, 500.0, flatGround(50.0));
    const glm::dvec3 point{8000.0, -3000.0, 50.0};
    EXPECT_EQ(controller.pivot(), point);
    EXPECT_LT(angleBetween(camera.forward(), point - camera.position), 1e-9);
    EXPECT_NEAR(camera.position.z, 550.0, 1e-6);
}

TEST(CameraController, FlyAfterOrbitKeepsTheView) {
    Camera camera = startCamera();
    CameraController controller;
    controller.orbit(camera, {1500.0, 2600.0, 120.0});
    const Camera orbiting = camera;
    controller.fly();
    EXPECT_EQ(controller.mode(), CameraMode::Fly);
    controller.update(camera, {}, 1.0 / 60.0, flatGround(0.0));
    EXPECT_EQ(camera.position, orbiting.position);
    EXPECT_EQ(camera.yaw, orbiting.yaw);
    EXPECT_EQ(camera.pitch, orbiting.pitch);
}

TEST(CameraController, ViewRayAndDepthPickInvertTheProjection) {
    Camera camera = startCamera();
    const glm::dvec3 centre = viewRay(camera, 400.0, 300.0);
    EXPECT_LT(angleBetween(centre, camera.forward()), 1e-12);
    // The top edge of the viewport is half the vertical field of view above the axis.
    const glm::dvec3 top = viewRay(camera, 400.0, 0.0);
    EXPECT_NEAR(angleBetween(top, camera.forward()), 0.5 * camera.fovY, 1e-12);
    EXPECT_GT(glm::dot(top, camera.up()), 0.0);
    const glm::dvec3 right = viewRay(camera, 800.0, 300.0);
    EXPECT_NEAR(angleBetween(right, camera.forward()), 0.5 * camera.fovX(), 1e-12);
    EXPECT_GT(glm::dot(right, camera.right()), 0.0);

    // Project world points with the renderer's matrices, then pick them back.
    const glm::dvec3 points[] = {
        {1800.0, 2900.0, 150.0}, {900.0, 2600.0, 40.0}, {1200.0, 5000.0, 300.0}};
    for (const glm::dvec3& world : points) {
        const glm::dvec4 clip =
            camera.relativeViewProjection() * glm::dvec4(world - camera.position, 1.0);
        ASSERT_GT(clip.w, 0.0);
        const double ndcX = clip.x / clip.w, ndcY = clip.y / clip.w, depth = clip.z / clip.w;
        const double xPx = (ndcX + 1.0) * 0.5 * camera.viewportWidth;
        const double yPx = (1.0 - ndcY) * 0.5 * camera.viewportHeight;
        const glm::dvec3 picked = pointAtDepth(camera, xPx, yPx, depth);
        EXPECT_LT(glm::length(picked - world), 1e-6) << world.x << ", " << world.y;
    }
}

TEST(CameraController, PlaneHitOrPointAhead) {
    const glm::dvec3 origin{0.0, 0.0, 100.0};
    const glm::dvec3 down = glm::normalize(glm::dvec3(1.0, 0.0, -1.0));
    const glm::dvec3 hit = pointOnPlaneOrAhead(origin, down, 0.0, 1000.0);
    EXPECT_NEAR(hit.x, 100.0, 1e-9);
    EXPECT_NEAR(hit.z, 0.0, 1e-9);
    // Too far, pointing up, or starting below the plane: the point at the maximum distance.
    EXPECT_NEAR(glm::length(pointOnPlaneOrAhead(origin, down, 0.0, 50.0) - origin), 50.0, 1e-9);
    const glm::dvec3 up = glm::normalize(glm::dvec3(1.0, 0.0, 0.5));
    EXPECT_NEAR(glm::length(pointOnPlaneOrAhead(origin, up, 0.0, 70.0) - origin), 70.0, 1e-9);
    EXPECT_NEAR(pointOnPlaneOrAhead(origin, down, 200.0, 30.0).z, 100.0 - 30.0 / std::sqrt(2.0),
                1e-9);
}

}  // namespace
}  // namespace terrain::runtime
