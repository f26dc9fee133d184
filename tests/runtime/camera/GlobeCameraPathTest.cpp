// GlobeCameraPath: keyframes are hit exactly, longitude crosses the antimeridian the short
// way, the descent from orbit is exponential (asinh) and never undershoots, also below sea
// level, files round-trip and every load error names the file and the problem (a planar path
// given for a globe included), and the documented example loads.
#include "terrain/runtime/GlobeCameraPath.h"

#include "TempFolder.h"

#include "terrain/globe/Wgs84.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

namespace terrain::runtime {
namespace {

GlobeKeyframe key(double t, double lat, double lon, double height, double heading = 0.0,
                  double pitch = -90.0, double fov = 50.0) {
    return {t, {{lat, lon, height}, heading, pitch}, fov};
}

GlobeCameraPath pathOf(std::vector<GlobeKeyframe> keyframes) {
    auto path = GlobeCameraPath::fromKeyframes(std::move(keyframes));
    EXPECT_TRUE(path) << path.error().message;
    return std::move(path).value();
}

TEST(GlobeCameraPath, HitsEveryKeyframe) {
    const std::vector<GlobeKeyframe> keys = {key(0, 10, 20, 1e6, 30, -60),
                                             key(5, 11, 22, 1e4, 80, -30, 60),
                                             key(9, 12, 21, -200, 100, 10, 40)};
    const GlobeCameraPath path = pathOf(keys);
    for (const GlobeKeyframe& k : keys) {
        const GlobePose p = path.poseAt(k.timeS);
        EXPECT_NEAR(p.where.latitudeDeg, k.pose.where.latitudeDeg, 1e-12);
        EXPECT_NEAR(p.where.longitudeDeg, k.pose.where.longitudeDeg, 1e-12);
        EXPECT_NEAR(p.where.height, k.pose.where.height, 1e-9 * std::abs(k.pose.where.height));
        EXPECT_NEAR(p.headingDeg, k.pose.headingDeg, 1e-12);
        EXPECT_NEAR(p.pitchDeg, k.pose.pitchDeg, 1e-12);
        EXPECT_NEAR(path.fovYDegreesAt(k.timeS), k.fovYDegrees, 1e-12);
    }
    EXPECT_EQ(path.poseAt(-5.0).where.height, path.poseAt(0.0).where.height);
    EXPECT_NEAR(path.poseAt(99.0).where.height, -200.0, 1e-9);
}

TEST(GlobeCameraPath, CrossesTheAntimeridianTheShortWay) {
    const GlobeCameraPath path =
        pathOf({key(0, 0, 179.0, 1e4, 170), key(10, 0, -179.0, 1e4, -170)});
    for (double t = 0.0; t <= 10.0; t += 0.25) {
        const GlobePose p = path.poseAt(t);
        EXPECT_GE(std::abs(p.where.longitudeDeg), 179.0 - 1e-9) << t;
        EXPECT_GE(std::abs(p.headingDeg), 170.0 - 1e-9) << t;  // turns through south
    }
    EXPECT_NEAR(std::abs(path.poseAt(5.0).where.longitudeDeg), 180.0, 1e-9);
}

TEST(GlobeCameraPath, FromOrbitDescendsExponentiallyToTheGivenHeight) {
    const double ground = 4391.0, end = ground + 1.0;
    const GlobeCameraPath path = GlobeCameraPath::fromOrbit(46.85, -121.76, end, 20.0);
    EXPECT_NEAR(path.poseAt(0.0).where.height, GlobeCameraPath::kOrbitHeightM, 1e-3);
    EXPECT_NEAR(path.poseAt(20.0).where.height, end, 1e-6);
    EXPECT_NEAR(path.poseAt(20.0).pitchDeg, -5.0, 1e-12);
    double previous = path.poseAt(0.0).where.height;
    for (double t = 0.1; t <= 20.0; t += 0.1) {
        const GlobePose p = path.poseAt(t);
        EXPECT_LT(p.where.height, previous) << t;
        EXPECT_GE(p.where.height, end - 1e-6) << t;
        EXPECT_DOUBLE_EQ(p.where.latitudeDeg, 46.85);
        if (t <= 12.0) {
            EXPECT_NEAR(p.pitchDeg, -90.0, 1e-9) << t;
        }
        previous = p.where.height;
    }
    // Exponential: the halfway height is near the geometric mean of the two ends.
    const double mid = path.poseAt(10.0).where.height;
    EXPECT_NEAR(std::log(mid), 0.5 * (std::log(GlobeCameraPath::kOrbitHeightM) + std::log(end)),
                0.7);
    // Below sea level (1 m above the Dead Sea's shore): still monotone, never below the end.
    const GlobeCameraPath low = GlobeCameraPath::fromOrbit(31.5, 35.5, -429.0, 20.0);
    previous = low.poseAt(0.0).where.height;
    for (double t = 0.1; t <= 20.0; t += 0.1) {
        const double h = low.poseAt(t).where.height;
        EXPECT_LT(h, previous) << t;
        EXPECT_GE(h, -429.0 - 1e-6) << t;
        previous = h;
    }
}

// The default flight over several places (issue 52: it visited one source of a composite):
// each stop reached and held in turn, never below the lower of two stops' ends on the way
// between them (straight up, across high, straight down: no ground is crossed low), across the
// antimeridian the short way; one stop is fromOrbit exactly.
TEST(GlobeCameraPath, FromTourVisitsEveryStopInTurn) {
    const std::vector<GlobeTourStop> stops = {
        {46.85, -121.76, 4392.0}, {57.5, 11.5, 51.0}, {-17.5, 179.5, 1.0}, {-16.5, -179.0, 2.0}};
    const double duration = 40.0;
    const GlobeCameraPath path = GlobeCameraPath::fromTour(stops, duration);
    EXPECT_EQ(path.durationS(), duration);
    const GlobePose first = path.poseAt(0.0);
    EXPECT_NEAR(first.where.height, GlobeCameraPath::kOrbitHeightM, 1e-3);
    EXPECT_DOUBLE_EQ(first.where.latitudeDeg, 46.85);
    EXPECT_DOUBLE_EQ(first.where.longitudeDeg, -121.76);
    for (std::size_t i = 0; i < stops.size(); ++i) {
        const double arrival = GlobeCameraPath::tourArrivalS(i, stops.size(), duration);
        const double shareEnd = duration * double(i + 1) / double(stops.size());
        EXPECT_LE(arrival, shareEnd) << i;
        EXPECT_GT(arrival, duration * double(i) / double(stops.size())) << i;
        for (const double t : {arrival, 0.5 * (arrival + shareEnd), shareEnd}) {  // held
            const GlobePose p = path.poseAt(t);
            EXPECT_NEAR(p.where.latitudeDeg, stops[i].latitudeDeg, 1e-9) << i << " at " << t;
            EXPECT_NEAR(std::remainder(p.where.longitudeDeg - stops[i].longitudeDeg, 360.0), 0.0,
                        1e-9)
                << i << " at " << t;
            EXPECT_NEAR(p.where.height, stops[i].endHeightM, 1e-6) << i << " at " << t;
            EXPECT_NEAR(p.pitchDeg, -5.0, 1e-9) << i << " at " << t;
        }
    }
    EXPECT_EQ(GlobeCameraPath::tourArrivalS(3, 4, duration), duration);
    // Between two stops: never below the lower end, and above 10 km wherever the camera is
    // away from both.
    for (std::size_t i = 1; i < stops.size(); ++i) {
        const double from = GlobeCameraPath::tourArrivalS(i - 1, stops.size(), duration);
        const double to = GlobeCameraPath::tourArrivalS(i, stops.size(), duration);
        const double lowest = std::min(stops[i - 1].endHeightM, stops[i].endHeightM);
        for (double t = from; t <= to; t += 0.01) {
            const GlobePose p = path.poseAt(t);
            EXPECT_GE(p.where.height, lowest - 1e-6) << t;
            const auto at = [&](const GlobeTourStop& s) {
                return std::abs(p.where.latitudeDeg - s.latitudeDeg) < 1e-9 &&
                       std::abs(std::remainder(p.where.longitudeDeg - s.longitudeDeg, 360.0)) <
                           1e-9;
            };
            if (!at(stops[i - 1]) && !at(stops[i])) {
                EXPECT_GE(p.where.height, 10e3) << t;
            }
            if (i == 3) {
                EXPECT_GE(std::abs(p.where.longitudeDeg), 179.0 - 1e-9) << t;
            }
        }
    }
    // Rainier to Sweden: high enough for both to be in view (the distance, ~7,900 km).
    EXPECT_GT(path.poseAt(0.3 * duration / 4.0 + duration / 4.0).where.height, 7e6);

    const GlobeTourStop one[] = {{46.85, -121.76, 4392.0}};
    const GlobeCameraPath alone = GlobeCameraPath::fromTour(one, 20.0);
    const GlobeCameraPath orbit = GlobeCameraPath::fromOrbit(46.85, -121.76, 4392.0, 20.0);
    ASSERT_EQ(alone.keyframes().size(), orbit.keyframes().size());
    for (std::size_t k = 0; k < orbit.keyframes().size(); ++k) {
        EXPECT_EQ(alone.keyframes()[k].timeS, orbit.keyframes()[k].timeS);
        EXPECT_EQ(alone.keyframes()[k].pose.where.height, orbit.keyframes()[k].pose.where.height);
        EXPECT_EQ(alone.keyframes()[k].pose.pitchDeg, orbit.keyframes()[k].pose.pitchDeg);
    }
    EXPECT_EQ(GlobeCameraPath::tourArrivalS(0, 1, 20.0), 20.0);
}

TEST(GlobeCameraPath, ApplyPlacesTheCameraOnTheGlobe) {
    const GlobeCameraPath path = pathOf({key(0, -89.9995, 45.0, 800.0, 0, -90, 40)});
    Camera camera;
    camera.viewportWidth = 640;
    path.apply(0.0, camera);
    const glm::dvec3 expected = globe::Wgs84::toEcef({-89.9995, 45.0, 800.0});
    EXPECT_LT(glm::length(camera.position - expected), 1e-6);
    EXPECT_NEAR(camera.fovY, 40.0 * std::numbers::pi / 180.0, 1e-12);
    EXPECT_EQ(camera.viewportWidth, 640);
    EXPECT_EQ(camera.nearPlane, kGlobeNearPlaneM);
}

TEST(GlobeCameraPath, RejectsBadKeyframes) {
    const auto error = [](std::vector<GlobeKeyframe> keys) {
        auto path = GlobeCameraPath::fromKeyframes(std::move(keys));
        return path ? std::string("no error") : path.error().message;
    };
    EXPECT_NE(error({}).find("is empty"), std::string::npos);
    EXPECT_NE(error({key(0, 91, 0, 10)}).find("keyframes[0].latitude_deg"), std::string::npos);
    EXPECT_NE(error({key(0, 0, 0, 10), key(0, 0, 0, 10)}).find("keyframes[1].time_s"),
              std::string::npos);
    EXPECT_NE(error({key(0, 0, 0, 2e9)}).find("keyframes[0].height_m"), std::string::npos);
    EXPECT_NE(error({key(0, 0, 0, 10, 0, -95)}).find("pitch_deg"), std::string::npos);
    EXPECT_NE(error({key(0, 0, 0, 10, 0, 0, 180)}).find("fov_y_deg"), std::string::npos);
    EXPECT_NE(error({key(0, 0, std::nan(""), 10)}).find("longitude_deg"), std::string::npos);
    EXPECT_NE(error({key(0, 0, 0, 10), key(1e-308, 0, 0, 10, 170)}).find("overflows"),
              std::string::npos);
}

TEST(GlobeCameraPathFile, SaveLoadRoundTripAndErrorsNameTheFile) {
    test::TempFolder temp;
    const GlobeCameraPath path = GlobeCameraPath::fromOrbit(35.26439, 45.0, 1.0, 12.0);
    const std::filesystem::path file = temp.path() / "flight.json";
    ASSERT_TRUE(path.save(file));
    auto loaded = GlobeCameraPath::load(file);
    ASSERT_TRUE(loaded) << loaded.error().message;
    ASSERT_EQ(loaded.value().keyframes().size(), path.keyframes().size());
    for (double t = 0.0; t <= 12.0; t += 0.5)
        EXPECT_DOUBLE_EQ(loaded.value().poseAt(t).where.height, path.poseAt(t).where.height);

    const auto errorFor = [&](const std::string& text) {
        const std::filesystem::path bad = temp.path() / "bad.json";
        std::ofstream(bad) << text;
        auto read = GlobeCameraPath::load(bad);
        const std::string message = read ? std::string("no error") : read.error().message;
        EXPECT_EQ(message.rfind(bad.string(), 0), 0u) << message;
        return message;
    };
    const std::string head = R"({"format": "terrain-globe-camera-path", "version": 1, )";
    EXPECT_NE(errorFor("{").find("not valid JSON"), std::string::npos);
    EXPECT_NE(errorFor(R"({"format": "terrain-camera-path", "version": 1, "keyframes": []})")
                  .find("a planar camera path"),
              std::string::npos);
    EXPECT_NE(errorFor(head + R"("keyframes": [{"time_s": 0, "position_m": [0, 0, 0]}]})")
                  .find("\"position_m\" is a planar camera path's key"),
              std::string::npos);
    EXPECT_NE(errorFor(head + R"("keyframes": [{"time_s": 0, "latitude_deg": 0}]})")
                  .find("keyframes[0]: missing \"longitude_deg\""),
              std::string::npos);
    EXPECT_NE(
        errorFor(head + R"("keyframes": [{"time_s": 0, "lat": 0}]})").find("unknown key \"lat\""),
        std::string::npos);
    EXPECT_NE(errorFor(head + R"("keyframes": [{"time_s": 0, "latitude_deg": 95,
        "longitude_deg": 0, "height_m": 1, "heading_deg": 0, "pitch_deg": 0, "fov_y_deg": 50}]})")
                  .find("keyframes[0].latitude_deg is 95"),
              std::string::npos);
    EXPECT_NE(GlobeCameraPath::load(temp.path() / "none.json").error().message.find("no such file"),
              std::string::npos);
}

TEST(GlobeCameraPathExample, RainierLoads) {
    auto path = GlobeCameraPath::load(std::filesystem::path(TERRAIN_SOURCE_DIR) / "docs" /
                                      "examples" / "rainier.globe-camera.json");
    ASSERT_TRUE(path) << path.error().message;
    EXPECT_EQ(path.value().durationS(), 20.0);
    EXPECT_NEAR(path.value().poseAt(20.0).where.height, 4400.0, 1e-6);
}

}  // namespace
}  // namespace terrain::runtime
