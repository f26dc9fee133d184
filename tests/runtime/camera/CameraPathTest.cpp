// CameraPath: keyframes are hit exactly, playback is continuous (jumps shrink with the
// sampling step), yaw turns the short way round, files round-trip and every load error
// names the file and the problem, the default path sees the DEM from every frame on tiny,
// huge, long and geographic pyramids, and the documented example file loads.
#include "terrain/runtime/CameraPath.h"

#include "TempFolder.h"

#include "terrain/pyramid/PyramidLayout.h"
#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/TerrainGeometry.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

namespace terrain::runtime {
namespace {

constexpr double kPi = std::numbers::pi;

double rad(double degrees) { return degrees * kPi / 180.0; }

// atan2 of |a × b| and a · b: accurate for tiny angles too, where acos of a dot product
// cannot resolve anything below ~1e-8.
double angleBetween(const glm::dvec3& a, const glm::dvec3& b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

Camera cameraAt(const CameraPath& path, double timeS) {
    Camera camera;
    path.apply(timeS, camera);
    return camera;
}

glm::dvec3 forwardOf(double yaw, double pitch) {
    Camera camera;
    camera.yaw = yaw;
    camera.pitch = pitch;
    return camera.forward();
}

CameraKeyframe lookAtKeyframe(double t, glm::dvec3 position, glm::dvec3 target, double fov = 60.0) {
    return {.timeS = t, .position = position, .lookAt = target, .fovYDegrees = fov};
}

CameraKeyframe yawPitchKeyframe(double t, glm::dvec3 position, double yawDeg, double pitchDeg,
                                double fov = 60.0) {
    return {.timeS = t,
            .position = position,
            .lookAt = std::nullopt,
            .yaw = rad(yawDeg),
            .pitch = rad(pitchDeg),
            .fovYDegrees = fov};
}

// Both kinds of keyframe, unevenly spaced in time, with turns and a climb.
std::vector<CameraKeyframe> mixedKeyframes() {
    return {
        lookAtKeyframe(0.0, {0.0, -1000.0, 500.0}, {2000.0, -2000.0, 0.0}, 50.0),
        lookAtKeyframe(1.5, {800.0, -1200.0, 450.0}, {2500.0, -1500.0, 0.0}, 55.0),
        yawPitchKeyframe(2.0, {1500.0, -1100.0, 600.0}, 350.0, -20.0, 60.0),
        yawPitchKeyframe(5.0, {2500.0, -300.0, 1500.0}, 10.0, -35.0, 70.0),
        lookAtKeyframe(6.0, {3000.0, 200.0, 2500.0}, {1000.0, -1000.0, 100.0}, 65.0),
        lookAtKeyframe(9.5, {500.0, 1500.0, 4000.0}, {1000.0, -1000.0, 100.0}, 60.0),
    };
}

CameraPath mixedPath() { return CameraPath::fromKeyframes(mixedKeyframes()).value(); }

// The view direction a keyframe asks for.
glm::dvec3 keyframeForward(const CameraKeyframe& k) {
    if (k.lookAt) return glm::normalize(*k.lookAt - k.position);
    return forwardOf(k.yaw, k.pitch);
}

struct Jumps {
    double positionM = 0.0;
    double directionRad = 0.0;
    double fovRad = 0.0;
};

// The largest change between neighbouring samples `step` seconds apart over the path.
Jumps largestJumps(const CameraPath& path, double step) {
    Jumps jumps;
    Camera previous = cameraAt(path, path.startS());
    const auto steps = static_cast<std::int64_t>(std::ceil(path.durationS() / step));
    for (std::int64_t i = 1; i <= steps; ++i) {
        const Camera camera = cameraAt(path, path.startS() + static_cast<double>(i) * step);
        jumps.positionM =
            std::max(jumps.positionM, glm::length(camera.position - previous.position));
        jumps.directionRad =
            std::max(jumps.directionRad, angleBetween(camera.forward(), previous.forward()));
        jumps.fovRad = std::max(jumps.fovRad, std::abs(camera.fovY - previous.fovY));
        previous = camera;
    }
    return jumps;
}

// The smallest cosine between the camera's motion over one sampling step and the chord of
// the segment it is on: negative when the camera backs up along its way.
double leastForwardMotion(const CameraPath& path, double step) {
    const auto& k = path.keyframes();
    double least = 1.0;
    std::size_t segment = 0;
    const auto steps = static_cast<std::int64_t>(std::floor(path.durationS() / step));
    for (std::int64_t i = 0; i < steps; ++i) {
        const double t = path.startS() + static_cast<double>(i) * step;
        while (segment + 2 < k.size() && k[segment + 1].timeS <= t) ++segment;
        if (t + step > k[segment + 1].timeS) continue;  // the step straddles a keyframe
        const glm::dvec3 chord = k[segment + 1].position - k[segment].position;
        const glm::dvec3 motion = cameraAt(path, t + step).position - cameraAt(path, t).position;
        if (glm::length(chord) == 0.0 || glm::length(motion) == 0.0) continue;
        least =
            std::min(least, glm::dot(chord, motion) / (glm::length(chord) * glm::length(motion)));
    }
    return least;
}

std::string readText(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

void writeText(const std::filesystem::path& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << text;
}

// ---- Keyframes and playback ------------------------------------------------------------

TEST(CameraPath, HitsEveryKeyframeExactly) {
    const CameraPath path = mixedPath();
    for (const CameraKeyframe& k : path.keyframes()) {
        Camera camera = cameraAt(path, k.timeS);
        EXPECT_EQ(camera.position, k.position) << "t = " << k.timeS;
        EXPECT_LT(angleBetween(camera.forward(), keyframeForward(k)), 1e-12) << "t = " << k.timeS;
        EXPECT_NEAR(camera.fovY, rad(k.fovYDegrees), 1e-15) << "t = " << k.timeS;
    }
}

TEST(CameraPath, DurationStartAndEnd) {
    const CameraPath path = mixedPath();
    EXPECT_EQ(path.startS(), 0.0);
    EXPECT_EQ(path.endS(), 9.5);
    EXPECT_EQ(path.durationS(), 9.5);
    EXPECT_EQ(path.keyframes().size(), mixedKeyframes().size());

    std::vector<CameraKeyframe> late = mixedKeyframes();
    for (CameraKeyframe& k : late) k.timeS += 100.0;
    const CameraPath shifted = CameraPath::fromKeyframes(late).value();
    EXPECT_EQ(shifted.startS(), 100.0);
    EXPECT_DOUBLE_EQ(shifted.durationS(), 9.5);
}

TEST(CameraPath, ClampsTimeToThePath) {
    const CameraPath path = mixedPath();
    const Camera first = cameraAt(path, 0.0);
    const Camera last = cameraAt(path, 9.5);
    for (double t : {-1.0, -1e300, -std::numeric_limits<double>::infinity(),
                     std::numeric_limits<double>::quiet_NaN()}) {
        const Camera c = cameraAt(path, t);
        EXPECT_EQ(c.position, first.position) << t;
        EXPECT_EQ(c.yaw, first.yaw) << t;
        EXPECT_EQ(c.pitch, first.pitch) << t;
        EXPECT_EQ(c.fovY, first.fovY) << t;
    }
    for (double t : {9.5000001, 1e300, std::numeric_limits<double>::infinity()}) {
        const Camera c = cameraAt(path, t);
        EXPECT_EQ(c.position, last.position) << t;
        EXPECT_EQ(c.yaw, last.yaw) << t;
        EXPECT_EQ(c.pitch, last.pitch) << t;
    }
}

TEST(CameraPath, LeavesViewportAndNearPlaneAlone) {
    const CameraPath path = mixedPath();
    Camera camera;
    camera.viewportWidth = 1920;
    camera.viewportHeight = 1080;
    camera.nearPlane = 0.25;
    path.apply(3.3, camera);
    EXPECT_EQ(camera.viewportWidth, 1920);
    EXPECT_EQ(camera.viewportHeight, 1080);
    EXPECT_EQ(camera.nearPlane, 0.25);
}

TEST(CameraPath, IsDeterministic) {
    const CameraPath a = mixedPath();
    const CameraPath b = mixedPath();
    for (double t = 0.0; t <= 9.5; t += 0.137) {
        const Camera ca = cameraAt(a, t);
        const Camera cb = cameraAt(b, t);
        EXPECT_EQ(ca.position, cb.position);
        EXPECT_EQ(ca.yaw, cb.yaw);
        EXPECT_EQ(ca.pitch, cb.pitch);
        EXPECT_EQ(ca.fovY, cb.fovY);
    }
}

TEST(CameraPath, IsContinuous) {
    const CameraPath path = mixedPath();
    // Between samples dt apart nothing moves further than a speed bound times dt: the
    // Hermite speed is at most 3.5× the fastest chord speed with Catmull–Rom tangents.
    double chordSpeed = 0.0;
    const auto& k = path.keyframes();
    for (std::size_t i = 1; i < k.size(); ++i)
        chordSpeed = std::max(chordSpeed, glm::length(k[i].position - k[i - 1].position) /
                                              (k[i].timeS - k[i - 1].timeS));
    const Jumps coarse = largestJumps(path, 1e-3);
    const Jumps fine = largestJumps(path, 1e-4);
    EXPECT_LE(coarse.positionM, 4.0 * chordSpeed * 1e-3);
    EXPECT_LE(fine.positionM, 4.0 * chordSpeed * 1e-4);
    // Continuous: ten times finer sampling, (about) ten times smaller largest jump.
    EXPECT_LT(fine.positionM, 0.2 * coarse.positionM);
    EXPECT_LT(fine.directionRad, 0.2 * coarse.directionRad);
    EXPECT_LT(fine.fovRad, 0.2 * coarse.fovRad);
    EXPECT_LT(coarse.directionRad, rad(1.0));

    // Across each keyframe, including where look-at and yaw/pitch keyframes meet.
    for (const CameraKeyframe& keyframe : k) {
        const Camera before = cameraAt(path, keyframe.timeS - 1e-7);
        const Camera after = cameraAt(path, keyframe.timeS + 1e-7);
        EXPECT_LT(glm::length(after.position - before.position), 1e-7 * 4.0 * chordSpeed * 2.0)
            << "t = " << keyframe.timeS;
        EXPECT_LT(angleBetween(after.forward(), before.forward()), 1e-5)
            << "t = " << keyframe.timeS;
    }
}

TEST(CameraPath, VelocityIsContinuousAtKeyframes) {
    // Hermite with Catmull–Rom tangents in time: the finite-difference velocity on both
    // sides of an inner keyframe agrees, even with uneven keyframe spacing.
    const CameraPath path = mixedPath();
    const double h = 1e-5;
    for (std::size_t i = 1; i + 1 < path.keyframes().size(); ++i) {
        const double t = path.keyframes()[i].timeS;
        const glm::dvec3 p = cameraAt(path, t).position;
        const glm::dvec3 left = (p - cameraAt(path, t - h).position) / h;
        const glm::dvec3 right = (cameraAt(path, t + h).position - p) / h;
        EXPECT_LT(glm::length(left - right), 1e-3 * std::max(1.0, glm::length(left)))
            << "keyframe " << i;
    }
}

TEST(CameraPath, NeverBacksUpAfterAShortStep) {
    // A 10 m step followed by a 10 km step: plain Catmull–Rom would swing back ~700 m
    // before the long step; the limited tangents keep every segment moving forward.
    const CameraPath path =
        CameraPath::fromKeyframes({yawPitchKeyframe(0.0, {0.0, 0.0, 100.0}, 90.0, 0.0),
                                   yawPitchKeyframe(1.0, {10.0, 0.0, 100.0}, 90.0, 0.0),
                                   yawPitchKeyframe(2.0, {10'000.0, 0.0, 100.0}, 90.0, 0.0)})
            .value();
    double previousX = 0.0;
    for (double t = 0.0; t <= 2.0; t += 1.0 / 512.0) {
        const double x = cameraAt(path, t).position.x;
        EXPECT_GE(x, previousX) << "t = " << t;
        previousX = x;
    }
    EXPECT_GE(leastForwardMotion(mixedPath(), 1e-3), 0.0);
}

TEST(CameraPath, KeyframesAtOnePlaceHold) {
    const glm::dvec3 hold{500.0, -200.0, 300.0};
    const CameraPath path = CameraPath::fromKeyframes(
                                {lookAtKeyframe(0.0, {0.0, 0.0, 400.0}, {0.0, -900.0, 0.0}),
                                 lookAtKeyframe(1.0, hold, {200.0, -900.0, 0.0}),
                                 lookAtKeyframe(3.0, hold, {700.0, -900.0, 0.0}),
                                 lookAtKeyframe(4.0, {900.0, -800.0, 200.0}, {700.0, -900.0, 0.0})})
                                .value();
    for (double t = 1.0; t <= 3.0; t += 1.0 / 64.0)
        EXPECT_LT(glm::length(cameraAt(path, t).position - hold), 1e-9) << "t = " << t;
}

TEST(CameraPath, YawTurnsTheShortWay) {
    struct Turn {
        double fromDeg, toDeg, middleDeg;
    };
    const glm::dvec3 p{0.0, 0.0, 100.0};
    for (const Turn& turn : {Turn{350.0, 10.0, 0.0}, Turn{10.0, 350.0, 0.0},
                             Turn{-170.0, 170.0, 180.0}, Turn{710.0, 10.0, 0.0}}) {
        SCOPED_TRACE(testing::Message() << turn.fromDeg << " → " << turn.toDeg);
        const CameraPath path =
            CameraPath::fromKeyframes({yawPitchKeyframe(0.0, p, turn.fromDeg, 0.0),
                                       yawPitchKeyframe(1.0, p, turn.toDeg, 0.0)})
                .value();
        const glm::dvec3 from = forwardOf(rad(turn.fromDeg), 0.0);
        const glm::dvec3 to = forwardOf(rad(turn.toDeg), 0.0);
        const double total = angleBetween(from, to);
        EXPECT_NEAR(total, rad(20.0), 1e-9);
        double largest = 0.0;
        for (double t = 0.0; t <= 1.0; t += 1.0 / 256.0) {
            const glm::dvec3 f = cameraAt(path, t).forward();
            // On the short arc every direction lies within the 20° between the two ends.
            EXPECT_LE(angleBetween(f, from) + angleBetween(f, to), total + 1e-9) << "t = " << t;
            largest = std::max(largest, angleBetween(f, from));
        }
        EXPECT_NEAR(largest, total, 1e-9);
        const Camera middle = cameraAt(path, 0.5);
        EXPECT_LT(angleBetween(middle.forward(), forwardOf(rad(turn.middleDeg), 0.0)), 1e-9);
        EXPECT_LE(std::abs(middle.yaw), kPi);
    }
}

TEST(CameraPath, YawKeepsTurningPastAFullCircle) {
    // 0 → 120 → 240 → 360 → 480 degrees: each step is the short way, so the spline keeps
    // turning the same way round instead of snapping back.
    std::vector<CameraKeyframe> keyframes;
    for (int i = 0; i <= 4; ++i)
        keyframes.push_back(yawPitchKeyframe(i, {0.0, 0.0, 10.0}, 120.0 * i, 5.0));
    const CameraPath path = CameraPath::fromKeyframes(keyframes).value();
    // Counter-clockwise seen from above means yaw (clockwise from north) increasing: the
    // cross product of consecutive forwards keeps pointing down (−z).
    glm::dvec3 previous = cameraAt(path, 0.0).forward();
    for (double t = 0.01; t <= 4.0; t += 0.01) {
        const glm::dvec3 f = cameraAt(path, t).forward();
        EXPECT_LT(glm::cross(previous, f).z, 0.0) << "t = " << t;
        previous = f;
    }
}

TEST(CameraPath, LookAtSegmentsFollowTheTarget) {
    // Two look-at keyframes with the same target: the camera keeps it centred all the way.
    const glm::dvec3 target{100.0, -100.0, 0.0};
    const CameraPath path =
        CameraPath::fromKeyframes({lookAtKeyframe(0.0, {0.0, 0.0, 300.0}, target),
                                   lookAtKeyframe(4.0, {400.0, -300.0, 200.0}, target),
                                   lookAtKeyframe(8.0, {100.0, -500.0, 100.0}, target)})
            .value();
    for (double t = 0.0; t <= 8.0; t += 0.25) {
        const Camera c = cameraAt(path, t);
        EXPECT_LT(angleBetween(c.forward(), target - c.position), 1e-12) << "t = " << t;
    }
}

TEST(CameraPath, SingleKeyframeIsAStill) {
    const CameraPath path =
        CameraPath::fromKeyframes({yawPitchKeyframe(3.0, {1.0, 2.0, 3.0}, 90.0, -10.0, 45.0)})
            .value();
    EXPECT_EQ(path.durationS(), 0.0);
    for (double t : {0.0, 3.0, 10.0}) {
        const Camera c = cameraAt(path, t);
        EXPECT_EQ(c.position, glm::dvec3(1.0, 2.0, 3.0));
        EXPECT_NEAR(c.yaw, rad(90.0), 1e-15);
        EXPECT_NEAR(c.pitch, rad(-10.0), 1e-15);
        EXPECT_NEAR(c.fovY, rad(45.0), 1e-15);
    }
}

TEST(CameraPath, FieldOfViewStaysBetweenItsKeyframes) {
    const CameraPath path = mixedPath();
    const auto& k = path.keyframes();
    for (std::size_t i = 1; i < k.size(); ++i) {
        const double lo = rad(std::min(k[i - 1].fovYDegrees, k[i].fovYDegrees));
        const double hi = rad(std::max(k[i - 1].fovYDegrees, k[i].fovYDegrees));
        for (double s = 0.0; s <= 1.0; s += 1.0 / 64.0) {
            const double fov =
                cameraAt(path, k[i - 1].timeS + s * (k[i].timeS - k[i - 1].timeS)).fovY;
            EXPECT_GE(fov, lo - 1e-15);
            EXPECT_LE(fov, hi + 1e-15);
        }
    }
}

TEST(CameraPath, FromKeyframesRejectsBadKeyframes) {
    const auto problem = [](std::vector<CameraKeyframe> keyframes) {
        Result<CameraPath> path = CameraPath::fromKeyframes(std::move(keyframes));
        return path.ok() ? std::string("(accepted)") : path.error().message;
    };
    const glm::dvec3 p{0.0, 0.0, 10.0};
    EXPECT_NE(problem({}).find("at least one"), std::string::npos) << problem({});
    const std::string same =
        problem({yawPitchKeyframe(1.0, p, 0, 0), yawPitchKeyframe(1.0, p, 0, 0)});
    EXPECT_EQ(same.rfind("camera path: ", 0), 0u) << same;
    EXPECT_NE(same.find("keyframes[1].time_s"), std::string::npos) << same;
    EXPECT_NE(same.find("increase strictly"), std::string::npos) << same;
    const std::string back =
        problem({yawPitchKeyframe(2.0, p, 0, 0), yawPitchKeyframe(1.0, p, 0, 0)});
    EXPECT_NE(back.find("keyframes[1].time_s"), std::string::npos) << back;
    EXPECT_NE(problem({yawPitchKeyframe(0.0, p, 0, 0, 180.0)}).find("keyframes[0].fov_y_deg"),
              std::string::npos);
    EXPECT_NE(problem({yawPitchKeyframe(0.0, p, 0, 0, 0.0)}).find("fov_y_deg"), std::string::npos);
    EXPECT_NE(problem({yawPitchKeyframe(0.0, p, 0, 0, -5.0)}).find("fov_y_deg"), std::string::npos);
    EXPECT_NE(problem({yawPitchKeyframe(0.0, p, 0, 91.0)}).find("pitch_deg"), std::string::npos);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_NE(problem({yawPitchKeyframe(nan, p, 0, 0)}).find("time_s"), std::string::npos);
    EXPECT_NE(problem({yawPitchKeyframe(0.0, {nan, 0.0, 0.0}, 0, 0)}).find("position_m"),
              std::string::npos);
    EXPECT_NE(problem({yawPitchKeyframe(0.0, p, nan, 0)}).find("yaw_deg"), std::string::npos);
    EXPECT_NE(problem({yawPitchKeyframe(0.0, p, 0, 0, nan)}).find("fov_y_deg"), std::string::npos);
    EXPECT_NE(problem({lookAtKeyframe(0.0, p, p)}).find("look_at_m"), std::string::npos);
    const std::string overflow = problem({yawPitchKeyframe(0.0, {-1e300, 0.0, 0.0}, 0, 0),
                                          yawPitchKeyframe(1e-10, {1e300, 0.0, 0.0}, 0, 0)});
    EXPECT_NE(overflow.find("keyframes[0]: the speed toward a neighbouring keyframe overflows"),
              std::string::npos)
        << overflow;
    EXPECT_NE(problem({lookAtKeyframe(0.0, p, {nan, 0.0, 0.0})}).find("look_at_m"),
              std::string::npos);
}

// ---- Files -----------------------------------------------------------------------------

TEST(CameraPathFile, SaveLoadRoundTrip) {
    test::TempFolder folder;
    const std::filesystem::path file = folder.path() / "mixed.camera.json";
    // Awkward numbers: large world coordinates with fine fractions, tiny and odd values.
    std::vector<CameraKeyframe> keyframes = mixedKeyframes();
    keyframes[0].position = {6'378'137.123456789, -1.0 / 3.0, 1e-7};
    keyframes[2].yaw = 0.1 + 2.0 * kPi;
    keyframes[3].timeS = 4.999999999999;
    const CameraPath path = CameraPath::fromKeyframes(keyframes).value();
    ASSERT_TRUE(path.save(file).ok());
    // Written atomically: nothing but the file itself is left in the folder.
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(folder.path()),
                            std::filesystem::directory_iterator{}),
              1);

    Result<CameraPath> loaded = CameraPath::load(file);
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    const auto& a = path.keyframes();
    const auto& b = loaded.value().keyframes();
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        EXPECT_EQ(a[i].timeS, b[i].timeS);
        EXPECT_EQ(a[i].position, b[i].position);  // shortest round-trip decimal: bit-exact
        ASSERT_EQ(a[i].lookAt.has_value(), b[i].lookAt.has_value());
        if (a[i].lookAt) {
            EXPECT_EQ(*a[i].lookAt, *b[i].lookAt);
        } else {
            // Through degrees and back: a rounding or two.
            EXPECT_NEAR(a[i].yaw, b[i].yaw, 1e-14 * std::max(1.0, std::abs(a[i].yaw)));
            EXPECT_NEAR(a[i].pitch, b[i].pitch, 1e-14);
        }
        EXPECT_EQ(a[i].fovYDegrees, b[i].fovYDegrees);
    }
    for (double t = 0.0; t <= 9.5; t += 0.5) {
        const Camera ca = cameraAt(path, t);
        const Camera cb = cameraAt(loaded.value(), t);
        EXPECT_LE(glm::length(ca.position - cb.position), 1e-9 * glm::length(ca.position));
        EXPECT_LT(angleBetween(ca.forward(), cb.forward()), 1e-9);
    }

    // Saving again over the file replaces it with the same text.
    const std::string first = readText(file);
    ASSERT_TRUE(loaded.value().save(file).ok());
    EXPECT_EQ(readText(file), first);
}

TEST(CameraPathFile, SaveIntoAMissingFolderNamesThePath) {
    test::TempFolder folder;
    const std::filesystem::path file = folder.path() / "no-such-folder" / "p.camera.json";
    const Status status = mixedPath().save(file);
    ASSERT_FALSE(status.ok());
    EXPECT_NE(status.error().message.find(file.string()), std::string::npos)
        << status.error().message;
}

// A valid file to break one piece at a time.
constexpr const char* kValidFile = R"({
  "format": "terrain-camera-path",
  "version": 1,
  "description": "two keyframes",
  "units": {"position": "metres"},
  "keyframes": [
    {"time_s": 0, "position_m": [0, 0, 100], "yaw_deg": 350, "pitch_deg": -10, "fov_y_deg": 60},
    {"time_s": 2.5, "position_m": [100, 0, 120], "look_at_m": [50, -50, 0], "fov_y_deg": 55}
  ]
})";

std::string replaced(std::string text, const std::string& from, const std::string& to) {
    const std::size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
    return text;
}

TEST(CameraPathFile, LoadsAValidFile) {
    test::TempFolder folder;
    const std::filesystem::path file = folder.path() / "valid.camera.json";
    writeText(file, kValidFile);
    Result<CameraPath> path = CameraPath::load(file);
    ASSERT_TRUE(path.ok()) << path.error().message;
    const auto& k = path.value().keyframes();
    ASSERT_EQ(k.size(), 2u);
    EXPECT_EQ(k[0].timeS, 0.0);
    EXPECT_FALSE(k[0].lookAt.has_value());
    EXPECT_NEAR(k[0].yaw, rad(350.0), 1e-15);
    EXPECT_NEAR(k[0].pitch, rad(-10.0), 1e-15);
    EXPECT_EQ(k[1].position, glm::dvec3(100.0, 0.0, 120.0));
    ASSERT_TRUE(k[1].lookAt.has_value());
    EXPECT_EQ(*k[1].lookAt, glm::dvec3(50.0, -50.0, 0.0));
    EXPECT_EQ(k[1].fovYDegrees, 55.0);
    EXPECT_EQ(path.value().durationS(), 2.5);
}

struct BadFile {
    const char* name;
    std::string text;
    std::vector<std::string> mentions;  // what the message must say besides the path
};

TEST(CameraPathFile, LoadErrorsNameTheFileAndTheProblem) {
    const std::string good = kValidFile;
    const std::vector<BadFile> cases = {
        {"bad-json", replaced(good, "\"version\": 1,", "\"version\": 1"), {"not valid JSON"}},
        {"empty", "", {"not valid JSON"}},
        {"not-object", "[1, 2]", {"not a camera path"}},
        {"wrong-format",
         replaced(good, "terrain-camera-path", "terrain-pyramid"),
         {"not a camera path", "\"format\""}},
        {"globe-path",
         replaced(good, "terrain-camera-path", "terrain-globe-camera-path"),
         {"a globe camera path", "latitude"}},
        {"version", replaced(good, "\"version\": 1", "\"version\": 2"), {"version", "2"}},
        {"unknown-top-key",
         replaced(good, "\"description\"", "\"descripton\""),
         {"unknown key \"descripton\""}},
        {"unknown-unit-key",
         replaced(good, "{\"position\": \"metres\"}", "{\"height\": \"m\"}"),
         {"units", "unknown key \"height\""}},
        {"missing-keyframes",
         R"({"format": "terrain-camera-path", "version": 1})",
         {"missing \"keyframes\""}},
        {"empty-keyframes",
         R"({"format": "terrain-camera-path", "version": 1, "keyframes": []})",
         {"at least one keyframe"}},
        {"missing-fov",
         replaced(good, ", \"fov_y_deg\": 55", ""),
         {"keyframes[1]", "missing \"fov_y_deg\""}},
        {"missing-time",
         replaced(good, "\"time_s\": 2.5, ", ""),
         {"keyframes[1]", "missing \"time_s\""}},
        {"missing-view",
         replaced(good, "\"look_at_m\": [50, -50, 0], ", ""),
         {"keyframes[1]", "look_at_m", "yaw_deg"}},
        {"missing-pitch",
         replaced(good, "\"pitch_deg\": -10, ", ""),
         {"keyframes[0]", "missing \"pitch_deg\""}},
        {"unknown-key",
         replaced(good, "\"fov_y_deg\": 55", "\"fov_deg\": 55"),
         {"keyframes[1]", "unknown key \"fov_deg\""}},
        {"both-views",
         replaced(good, "\"look_at_m\"", "\"yaw_deg\": 3, \"look_at_m\""),
         {"keyframes[1]", "not both"}},
        {"wrong-type",
         replaced(good, "\"time_s\": 2.5", "\"time_s\": \"2.5\""),
         {"keyframes[1]", "\"time_s\" must be a number"}},
        {"short-position",
         replaced(good, "[100, 0, 120]", "[100, 0]"),
         {"keyframes[1]", "position_m", "3 numbers"}},
        {"keyframe-not-object",
         replaced(good, "{\"time_s\": 2.5", "7, {\"time_s\": 2.5"),
         {"keyframes[1]", "object"}},
        {"same-time",
         replaced(good, "\"time_s\": 2.5", "\"time_s\": 0"),
         {"keyframes[1].time_s", "increase strictly"}},
        {"earlier-time",
         replaced(good, "\"time_s\": 2.5", "\"time_s\": -1"),
         {"keyframes[1].time_s", "increase strictly"}},
        {"fov-180",
         replaced(good, "\"fov_y_deg\": 55", "\"fov_y_deg\": 180"),
         {"keyframes[1].fov_y_deg", "180"}},
        {"fov-0",
         replaced(good, "\"fov_y_deg\": 60", "\"fov_y_deg\": 0"),
         {"keyframes[0].fov_y_deg"}},
        {"pitch-95",
         replaced(good, "\"pitch_deg\": -10", "\"pitch_deg\": -95"),
         {"keyframes[0].pitch_deg", "-95"}},
        {"look-at-self",
         replaced(good, "[50, -50, 0]", "[100, 0, 120]"),
         {"keyframes[1].look_at_m"}},
        {"huge-number", replaced(good, "[100, 0, 120]", "[1e400, 0, 120]"), {}},
    };
    test::TempFolder folder;
    for (const BadFile& bad : cases) {
        const std::filesystem::path file = folder.path() / (std::string(bad.name) + ".camera.json");
        writeText(file, bad.text);
        Result<CameraPath> path = CameraPath::load(file);
        ASSERT_FALSE(path.ok()) << bad.name;
        const std::string& message = path.error().message;
        EXPECT_EQ(message.rfind(file.string() + ": ", 0), 0u) << bad.name << ": " << message;
        for (const std::string& mention : bad.mentions)
            EXPECT_NE(message.find(mention), std::string::npos)
                << bad.name << ": \"" << message << "\" should mention " << mention;
    }
}

TEST(CameraPathFile, MissingFileAndFolderNameThePath) {
    test::TempFolder folder;
    const std::filesystem::path missing = folder.path() / "missing.camera.json";
    Result<CameraPath> path = CameraPath::load(missing);
    ASSERT_FALSE(path.ok());
    EXPECT_EQ(path.error().message, missing.string() + ": no such file");
    Result<CameraPath> dir = CameraPath::load(folder.path());
    ASSERT_FALSE(dir.ok());
    EXPECT_EQ(dir.error().message.rfind(folder.path().string() + ": ", 0), 0u);
}

// ---- The default path ------------------------------------------------------------------

struct GeometryCase {
    const char* name;
    std::int64_t width;
    std::int64_t height;
    io::CrsKind crs;
    double spacingX;  // map units per column (degrees when geographic)
    double spacingY;
    double minHeight;
    double maxHeight;
    /// Projected: the georeferenced south-west corner (the procedural DEM's is 0, 0).
    glm::dvec2 southWestM{0.0, 0.0};
};

TerrainGeometry geometryOf(const GeometryCase& c) {
    io::PyramidManifest manifest =
        io::PyramidManifest::forLayout(io::PyramidLayout::create(c.width, c.height).value());
    manifest.georeference.crsKind = c.crs;
    manifest.georeference.pixelSizeX = c.spacingX;
    manifest.georeference.pixelSizeY = c.spacingY;
    if (c.crs == io::CrsKind::Geographic) {
        manifest.georeference.originX = 7.0;  // the Alps
        manifest.georeference.originY = 47.0;
        manifest.georeference.epsg = io::Georeference::kWgs84Geographic;
    } else if (c.crs == io::CrsKind::Projected) {
        manifest.georeference.originX = c.southWestM.x;
        manifest.georeference.originY = c.southWestM.y + static_cast<double>(c.height) * c.spacingY;
    }
    manifest.statistics.minHeight = c.minHeight;
    manifest.statistics.maxHeight = c.maxHeight;
    return TerrainGeometry(manifest);
}

const std::vector<GeometryCase>& geometryCases() {
    static const std::vector<GeometryCase> cases = {
        // terrain-build procedural:size=1025,seed=1
        {"procedural", 1025, 1025, io::CrsKind::Projected, 30.0, 30.0, 220.24, 4048.3},
        {"tiny", 37, 29, io::CrsKind::Projected, 30.0, 30.0, 0.0, 4000.0},
        {"tiny-unknown-crs", 37, 29, io::CrsKind::Unknown, 1.0, 1.0, 0.0, 100.0},
        {"flat", 65, 65, io::CrsKind::Projected, 10.0, 10.0, 0.0, 0.0},
        {"below-sea", 513, 257, io::CrsKind::Projected, 5.0, 5.0, -430.0, -380.0},
        {"huge", (std::int64_t{1} << 20) + 1, (std::int64_t{1} << 20) + 1, io::CrsKind::Projected,
         30.0, 30.0, -10.0, 8848.0},
        {"long", 8193, 513, io::CrsKind::Projected, 10.0, 10.0, 100.0, 900.0},
        {"tall", 257, 4097, io::CrsKind::Projected, 2.0, 2.0, 0.0, 50.0},
        {"geographic", 3601, 3601, io::CrsKind::Geographic, 1.0 / 3600.0, 1.0 / 3600.0, 190.0,
         4800.0},
        // 10,000 km from the CRS's origin, as a DEM far out on a planet-sized grid.
        {"far-from-origin",
         513,
         513,
         io::CrsKind::Projected,
         30.0,
         30.0,
         0.0,
         2000.0,
         {1.0e7, 1.0e7}},
    };
    return cases;
}

TEST(CameraPathDefault, EveryFrameLooksAtTheDem) {
    for (const GeometryCase& c : geometryCases()) {
        SCOPED_TRACE(c.name);
        const TerrainGeometry geometry = geometryOf(c);
        const glm::dvec2 size = geometry.demSize();
        const double margin = 1e-9 * std::max(size.x, size.y);
        const CameraPath path = CameraPath::defaultFor(geometry);
        EXPECT_GE(path.keyframes().size(), 6u);
        EXPECT_LE(path.keyframes().size(), 8u);

        double lowestClearance = std::numeric_limits<double>::infinity();
        double steepest = 0.0;
        double startZ = 0.0, endZ = 0.0;
        for (int i = 0; i <= 4000; ++i) {
            const double t = path.durationS() * i / 4000.0;
            const Camera camera = cameraAt(path, t);
            const glm::dvec3 f = camera.forward();
            ASSERT_LT(f.z, 0.0) << "t = " << t;
            const double along = (geometry.minHeight() - camera.position.z) / f.z;
            const glm::dvec3 hit = camera.position + along * f;
            const glm::dvec2 local = glm::dvec2(hit) - geometry.origin();  // y ≤ 0 on the DEM
            EXPECT_GE(local.x, -margin) << "t = " << t;
            EXPECT_LE(local.x, size.x + margin) << "t = " << t;
            EXPECT_GE(local.y, -size.y - margin) << "t = " << t;
            EXPECT_LE(local.y, margin) << "t = " << t;
            EXPECT_NEAR(camera.fovY, rad(60.0), 1e-12);
            lowestClearance = std::min(lowestClearance, camera.position.z - geometry.maxHeight());
            steepest = std::max(steepest, -camera.pitch);
            if (i == 0) startZ = camera.position.z;
            endZ = camera.position.z;
        }
        // Never below the highest point of the DEM, so never inside the terrain.
        EXPECT_GT(lowestClearance, 0.0);
        // Never straight down, where yaw is undefined and the picture would spin.
        EXPECT_LT(steepest, Camera::kMaxPitch - rad(1.0));
        // The low pass is the lowest part; the climb never dips below it.
        EXPECT_GE(lowestClearance, (startZ - geometry.maxHeight()) * (1.0 - 1e-12));
        EXPECT_GT(endZ, startZ);

        EXPECT_GE(leastForwardMotion(path, path.durationS() / 4000.0), 0.0);
        const Jumps coarse = largestJumps(path, path.durationS() / 2000.0);
        const Jumps fine = largestJumps(path, path.durationS() / 20000.0);
        EXPECT_LT(fine.positionM, 0.2 * coarse.positionM);
        EXPECT_LT(fine.directionRad, 0.2 * coarse.directionRad);
        EXPECT_LT(coarse.directionRad, rad(2.0));
    }
}

TEST(CameraPathDefault, StartsLowAndEndsWithTheWholeDemInView) {
    const TerrainGeometry geometry = geometryOf(geometryCases()[0]);
    const CameraPath path = CameraPath::defaultFor(geometry);
    const Camera start = cameraAt(path, 0.0);
    EXPECT_NEAR(start.position.z, 4048.3 + 600.0, 1e-9);  // maxHeight + 20 spacings
    EXPECT_LT(start.pitch, 0.0);
    EXPECT_GT(start.pitch, rad(-30.0));  // looking ahead, slightly down

    // The wide view: all four DEM corners (at the lowest height) inside the vertical and
    // horizontal field of view of a 16:9 viewport.
    Camera end;
    end.viewportWidth = 1600;
    end.viewportHeight = 900;
    path.apply(path.endS(), end);
    for (const glm::dvec2 corner :
         {geometry.worldAtFraction(0.0, 0.0), geometry.worldAtFraction(1.0, 0.0),
          geometry.worldAtFraction(0.0, 1.0), geometry.worldAtFraction(1.0, 1.0)}) {
        const glm::dvec3 d = glm::dvec3(corner, geometry.minHeight()) - end.position;
        const double depth = glm::dot(d, end.forward());
        ASSERT_GT(depth, 0.0);
        EXPECT_LE(std::abs(glm::dot(d, end.up())) / depth, std::tan(0.5 * end.fovY));
        EXPECT_LE(std::abs(glm::dot(d, end.right())) / depth, std::tan(0.5 * end.fovX()));
    }
}

TEST(CameraPathDefault, DurationAndKeyframeTimes) {
    const TerrainGeometry geometry = geometryOf(geometryCases()[0]);
    for (double duration : {20.0, 45.0, 0.5}) {
        const CameraPath path = CameraPath::defaultFor(geometry, duration);
        EXPECT_EQ(path.startS(), 0.0);
        EXPECT_DOUBLE_EQ(path.durationS(), duration);
        EXPECT_DOUBLE_EQ(path.endS(), duration);
        for (const CameraKeyframe& k : path.keyframes()) {
            EXPECT_TRUE(k.lookAt.has_value());
            EXPECT_EQ(k.fovYDegrees, 60.0);
        }
    }
    EXPECT_DOUBLE_EQ(CameraPath::defaultFor(geometry).durationS(), 20.0);
}

TEST(CameraPathDefault, SavesAndLoads) {
    test::TempFolder folder;
    const CameraPath path = CameraPath::defaultFor(geometryOf(geometryCases()[0]));
    const std::filesystem::path file = folder.path() / "default.camera.json";
    ASSERT_TRUE(path.save(file).ok());
    Result<CameraPath> loaded = CameraPath::load(file);
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    ASSERT_EQ(loaded.value().keyframes().size(), path.keyframes().size());
    for (std::size_t i = 0; i < path.keyframes().size(); ++i) {
        EXPECT_EQ(loaded.value().keyframes()[i].position, path.keyframes()[i].position);
        EXPECT_EQ(loaded.value().keyframes()[i].lookAt, path.keyframes()[i].lookAt);
    }
}

// ---- The documented example -------------------------------------------------------------

TEST(CameraPathExample, FlyoverLoadsAndLooksAtTheProceduralPyramid) {
    const std::filesystem::path file =
        std::filesystem::path(TERRAIN_SOURCE_DIR) / "docs" / "examples" / "flyover.camera.json";
    Result<CameraPath> path = CameraPath::load(file);
    ASSERT_TRUE(path.ok()) << path.error().message;
    EXPECT_GE(path.value().keyframes().size(), 4u);
    EXPECT_EQ(path.value().startS(), 0.0);

    // It is written for terrain-build procedural:size=1025,seed=1: every frame looks at
    // that DEM from above its highest point.
    const TerrainGeometry geometry = geometryOf(geometryCases()[0]);
    const glm::dvec2 size = geometry.demSize();
    for (int i = 0; i <= 2000; ++i) {
        const double t = path.value().durationS() * i / 2000.0;
        const Camera camera = cameraAt(path.value(), t);
        EXPECT_GT(camera.position.z, geometry.maxHeight()) << "t = " << t;
        const glm::dvec3 f = camera.forward();
        ASSERT_LT(f.z, 0.0) << "t = " << t;
        const glm::dvec3 hit =
            camera.position + (geometry.minHeight() - camera.position.z) / f.z * f;
        const glm::dvec2 local = glm::dvec2(hit) - geometry.origin();
        EXPECT_TRUE(local.x >= 0.0 && local.x <= size.x && local.y >= -size.y && local.y <= 0.0)
            << "t = " << t << ": the view meets the ground at (" << hit.x << ", " << hit.y << ")";
    }
}

TEST(CameraPathExample, TheExampleInTheDocsLoads) {
    const std::string doc =
        readText(std::filesystem::path(TERRAIN_SOURCE_DIR) / "docs" / "camera-path.md");
    const std::size_t begin = doc.find("```json\n");
    ASSERT_NE(begin, std::string::npos);
    const std::size_t end = doc.find("```", begin + 8);
    ASSERT_NE(end, std::string::npos);
    test::TempFolder folder;
    const std::filesystem::path file = folder.path() / "doc.camera.json";
    writeText(file, doc.substr(begin + 8, end - begin - 8));
    Result<CameraPath> path = CameraPath::load(file);
    ASSERT_TRUE(path.ok()) << path.error().message;
    EXPECT_EQ(path.value().keyframes().size(), 3u);
}

}  // namespace
}  // namespace terrain::runtime
