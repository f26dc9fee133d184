// verticalErrorPxPerM (EdgeTessellation.h): the fine LOD's bound on how long one metre of
// vertical error can look on screen anywhere in a box. For random cameras and boxes, every
// sampled vertical segment of the box whose ends are on screen (and so is all of it: a
// segment in front of the camera projects to a segment) is no longer than the bound says;
// and the bound is tight where it can be, for a small box straight ahead.
#include "terrain/runtime/Aabb.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/EdgeTessellation.h"
#include "terrain/runtime/ScreenProjection.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <iostream>
#include <numbers>
#include <optional>
#include <random>

namespace terrain::test {
namespace {

using runtime::Aabb;
using runtime::Camera;

constexpr double kDegrees = std::numbers::pi / 180.0;

// The pixel position of camera-relative `p`, if it is drawn: in front of the near plane
// and inside the viewport.
std::optional<glm::dvec2> onScreen(const Camera& c, const glm::dvec3& p) {
    const glm::dvec4 clip = c.relativeViewProjection() * glm::dvec4(p, 1.0);
    if (!(clip.w >= c.nearPlane)) return std::nullopt;
    const glm::dvec2 px =
        runtime::projectToPixels(c.relativeViewProjection(), c.viewportWidth, c.viewportHeight, p);
    if (px.x < 0.0 || px.y < 0.0 || px.x > c.viewportWidth || px.y > c.viewportHeight) {
        return std::nullopt;
    }
    return px;
}

TEST(VerticalErrorBound, NoVerticalSegmentOnScreenIsLongerThanTheBound) {
    std::mt19937_64 random(7);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    int segmentsOnScreen = 0;
    double closest = 0.0;  // the largest measured / bound, to show the test has teeth
    for (int trial = 0; trial < 2000; ++trial) {
        Camera c;
        c.viewportWidth = 160 + static_cast<int>(1760 * u(random));
        c.viewportHeight = 120 + static_cast<int>(960 * u(random));
        c.fovY = (30.0 + 60.0 * u(random)) * kDegrees;
        c.nearPlane = 0.5;
        c.yaw = 2.0 * std::numbers::pi * u(random);
        c.pitch = (-85.0 + 170.0 * u(random)) * kDegrees;
        // Boxes from a metre to kilometres across, near the camera, around it or far away.
        const double distance = std::pow(10.0, 4.0 * u(random));
        const glm::dvec3 centre =
            distance *
            glm::normalize(glm::dvec3(u(random) - 0.5, u(random) - 0.5, 0.5 * (u(random) - 0.5)));
        const glm::dvec3 half{std::pow(10.0, 3.0 * u(random)), std::pow(10.0, 3.0 * u(random)),
                              std::pow(10.0, 3.0 * u(random))};
        const Aabb box{.min = centre - half, .max = centre + half};
        const double bound = runtime::verticalErrorPxPerM(c.relativeViewProjection(),
                                                          {c.viewportWidth, c.viewportHeight}, box);
        ASSERT_TRUE(std::isfinite(bound) && bound > 0.0) << "trial " << trial;
        for (int s = 0; s < 64; ++s) {
            const double x = box.min.x + (box.max.x - box.min.x) * u(random);
            const double y = box.min.y + (box.max.y - box.min.y) * u(random);
            const double z0 = box.min.z + (box.max.z - box.min.z) * u(random);
            const double z1 = box.min.z + (box.max.z - box.min.z) * u(random);
            const auto a = onScreen(c, {x, y, z0});
            const auto b = onScreen(c, {x, y, z1});
            if (!a || !b || z0 == z1) continue;
            ++segmentsOnScreen;
            const double measured = glm::length(*a - *b) / std::abs(z1 - z0);
            closest = std::max(closest, measured / bound);
            EXPECT_LE(measured, bound * (1.0 + 1e-9))
                << "trial " << trial << ": segment at (" << x << ", " << y << ") from " << z0
                << " to " << z1 << " m";
        }
    }
    std::cout << "[          ] " << segmentsOnScreen
              << " segments on screen; largest measured / bound " << closest << "\n";
    EXPECT_GT(segmentsOnScreen, 5000);
    EXPECT_GT(closest, 0.9) << "the bound should be reached by some segment";
}

TEST(VerticalErrorBound, IsTightForASmallBoxStraightAhead) {
    Camera c;
    c.viewportWidth = 1024;
    c.viewportHeight = 768;
    c.fovY = 60.0 * kDegrees;
    c.nearPlane = 0.5;  // looking north, level
    const Aabb box{.min = {-0.5, 1000.0, -0.5}, .max = {0.5, 1001.0, 0.5}};
    const double bound = runtime::verticalErrorPxPerM(c.relativeViewProjection(),
                                                      {c.viewportWidth, c.viewportHeight}, box);
    // A metre straight ahead at 1 km: (H / 2) / tan(fovY / 2) / 1000 pixels.
    const double exact = 0.5 * c.viewportHeight / std::tan(0.5 * c.fovY) / 1000.0;
    EXPECT_GE(bound, exact);
    EXPECT_LE(bound, 1.01 * exact);
}

TEST(VerticalErrorBound, ABoxReachingBehindTheCameraIsBoundedByItsDistance) {
    // A flat block below the camera: its box reaches behind the camera, but it is 100 m
    // down, so nothing of it on screen is nearer than 100 m / √(1 + tan²x + tan²y).
    Camera c;
    c.viewportWidth = 800;
    c.viewportHeight = 600;
    c.fovY = 60.0 * kDegrees;
    c.nearPlane = 0.5;
    c.pitch = -20.0 * kDegrees;
    const Aabb box{.min = {-500.0, -500.0, -101.0}, .max = {500.0, 500.0, -100.0}};
    const double bound = runtime::verticalErrorPxPerM(c.relativeViewProjection(),
                                                      {c.viewportWidth, c.viewportHeight}, box);
    const double nearPlaneBound = 0.5 * c.viewportHeight / std::tan(0.5 * c.fovY) / c.nearPlane;
    EXPECT_LT(bound, nearPlaneBound / 50.0);
}

}  // namespace
}  // namespace terrain::test
