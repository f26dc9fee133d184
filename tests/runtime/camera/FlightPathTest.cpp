// FlightPath: the one reader picks the format from the file, refuses the other surface's format
// with the words CameraPath::load and GlobeCameraPath::load give, saves and plays the held path
// exactly as that path does, and fromCameras passes through the cameras it was given.
#include "terrain/runtime/FlightPath.h"

#include "TempFolder.h"

#include "terrain/runtime/GlobeCamera.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

namespace terrain::runtime {
namespace {

CameraPath planarPath() {
    auto path = CameraPath::fromKeyframes(
        {{0.0, {10.0, 20.0, 300.0}, std::nullopt, 0.3, -0.2, 60.0},
         {4.0, {500.0, 80.0, 900.0}, glm::dvec3{0.0, 0.0, 0.0}, 0.0, 0.0, 45.0},
         {9.5, {900.0, -40.0, 2000.0}, std::nullopt, -2.0, -1.0, 70.0}});
    EXPECT_TRUE(path) << path.error().message;
    return std::move(path).value();
}

void expectSameCamera(const Camera& a, const Camera& b) {
    EXPECT_EQ(a.position, b.position);
    EXPECT_EQ(a.yaw, b.yaw);
    EXPECT_EQ(a.pitch, b.pitch);
    EXPECT_EQ(a.fovY, b.fovY);
}

TEST(FlightPath, LoadPicksTheFormatFromTheFile) {
    test::TempFolder temp;
    const auto planarFile = temp.path() / "planar.json";
    const auto globeFile = temp.path() / "globe.json";
    ASSERT_TRUE(planarPath().save(planarFile));
    ASSERT_TRUE(GlobeCameraPath::fromOrbit(46.85, -121.76, 1.0, 12.0).save(globeFile));

    auto planar = FlightPath::load(planarFile);
    ASSERT_TRUE(planar) << planar.error().message;
    EXPECT_EQ(planar.value().frame(), PathFrame::Plane);
    ASSERT_NE(planar.value().planar(), nullptr);
    EXPECT_EQ(planar.value().globe(), nullptr);
    EXPECT_EQ(planar.value().durationS(), 9.5);

    auto globe = FlightPath::load(globeFile);
    ASSERT_TRUE(globe) << globe.error().message;
    EXPECT_EQ(globe.value().frame(), PathFrame::Globe);
    ASSERT_NE(globe.value().globe(), nullptr);
    EXPECT_EQ(globe.value().planar(), nullptr);
    EXPECT_EQ(globe.value().startS(), 0.0);
    EXPECT_EQ(globe.value().endS(), 12.0);
}

TEST(FlightPath, ASurfaceRefusesTheOtherSurfacesFormatAsThePathReadersDo) {
    test::TempFolder temp;
    const auto planarFile = temp.path() / "planar.json";
    const auto globeFile = temp.path() / "globe.json";
    ASSERT_TRUE(planarPath().save(planarFile));
    ASSERT_TRUE(GlobeCameraPath::fromOrbit(46.85, -121.76, 1.0, 12.0).save(globeFile));

    auto globeAsPlane = FlightPath::load(globeFile, PathFrame::Plane);
    ASSERT_FALSE(globeAsPlane);
    EXPECT_EQ(globeAsPlane.error().message,
              globeFile.string() +
                  ": a globe camera path (\"terrain-globe-camera-path\", latitude, longitude and "
                  "height); a planar pyramid flies a \"terrain-camera-path\" in its own metres "
                  "(docs/camera-path.md)");
    EXPECT_EQ(CameraPath::load(globeFile).error().message, globeAsPlane.error().message);

    auto planeAsGlobe = FlightPath::load(planarFile, PathFrame::Globe);
    ASSERT_FALSE(planeAsGlobe);
    EXPECT_EQ(planeAsGlobe.error().message,
              planarFile.string() +
                  ": a planar camera path (\"terrain-camera-path\", positions in metres); a globe "
                  "pyramid flies a \"terrain-globe-camera-path\" in latitude, longitude and "
                  "height (docs/camera-path.md, \"Globe camera paths\")");
    EXPECT_EQ(GlobeCameraPath::load(planarFile).error().message, planeAsGlobe.error().message);

    EXPECT_TRUE(FlightPath::load(planarFile, PathFrame::Plane));
    EXPECT_TRUE(FlightPath::load(globeFile, PathFrame::Globe));
}

TEST(FlightPath, AFileOfNeitherFormatIsRefusedAsAPlanarPath) {
    test::TempFolder temp;
    const auto file = temp.path() / "other.json";
    std::ofstream(file) << R"({"format": "something-else", "version": 1, "keyframes": []})";
    auto read = FlightPath::load(file);
    ASSERT_FALSE(read);
    EXPECT_EQ(read.error().message, CameraPath::load(file).error().message);
    EXPECT_NE(read.error().message.find("not a camera path: \"format\" must be "
                                        "\"terrain-camera-path\", not \"something-else\""),
              std::string::npos)
        << read.error().message;
    EXPECT_NE(FlightPath::load(temp.path() / "none.json").error().message.find("no such file"),
              std::string::npos);
}

TEST(FlightPath, SavesAndPlaysTheHeldPath) {
    test::TempFolder temp;
    const CameraPath planar = planarPath();
    const GlobeCameraPath globe = GlobeCameraPath::fromOrbit(-33.9, 151.2, 50.0, 8.0);
    for (const FlightPath& flight : {FlightPath(planar), FlightPath(globe)}) {
        const auto file = temp.path() / "flight.json";
        ASSERT_TRUE(flight.save(file));
        auto loaded = FlightPath::load(file);
        ASSERT_TRUE(loaded) << loaded.error().message;
        EXPECT_EQ(loaded.value().frame(), flight.frame());
        for (double t = -1.0; t <= flight.endS() + 1.0; t += 0.75) {
            Camera fromFlight, fromLoaded, fromPath;
            flight.apply(t, fromFlight);
            loaded.value().apply(t, fromLoaded);
            if (flight.planar())
                planar.apply(t, fromPath);
            else
                globe.apply(t, fromPath);
            expectSameCamera(fromFlight, fromPath);
            EXPECT_NEAR(fromLoaded.position.x, fromPath.position.x,
                        1e-9 * (1.0 + std::abs(fromPath.position.x)));
            EXPECT_NEAR(fromLoaded.fovY, fromPath.fovY, 1e-12);
        }
    }
}

TEST(FlightPath, FromCamerasPassesThroughEveryCamera) {
    // The plane: the cameras a flight had, at uneven times.
    std::vector<CameraSample> samples(3);
    samples[0].camera.position = {0.0, 0.0, 100.0};
    samples[1].timeS = 0.25;
    samples[1].camera.position = {30.0, 10.0, 120.0};
    samples[1].camera.yaw = 0.5;
    samples[1].camera.pitch = -0.3;
    samples[1].camera.fovY = 0.9;
    samples[2].timeS = 0.6;
    samples[2].camera.position = {60.0, 40.0, 110.0};
    samples[2].camera.yaw = -3.0;
    auto planar = FlightPath::fromCameras(PathFrame::Plane, samples);
    ASSERT_TRUE(planar) << planar.error().message;
    EXPECT_EQ(planar.value().frame(), PathFrame::Plane);
    for (const CameraSample& s : samples) {
        Camera played;
        planar.value().apply(s.timeS, played);
        EXPECT_NEAR(glm::length(played.position - s.camera.position), 0.0, 1e-9);
        EXPECT_NEAR(std::remainder(played.yaw - s.camera.yaw, 2.0 * std::numbers::pi), 0.0, 1e-12);
        EXPECT_NEAR(played.pitch, s.camera.pitch, 1e-12);
        EXPECT_NEAR(played.fovY, s.camera.fovY, 1e-12);
    }

    // The globe: cameras placed by pose, read back as poses.
    const std::vector<GlobePose> poses = {{{46.8, -121.7, 3000.0}, 10.0, -30.0},
                                          {{46.9, -121.6, 2500.0}, 40.0, -10.0}};
    std::vector<CameraSample> globeSamples(poses.size());
    for (std::size_t i = 0; i < poses.size(); ++i) {
        globeSamples[i].timeS = static_cast<double>(i) * 2.0;
        placeOnGlobe(globeSamples[i].camera, poses[i]);
    }
    auto globe = FlightPath::fromCameras(PathFrame::Globe, globeSamples);
    ASSERT_TRUE(globe) << globe.error().message;
    ASSERT_NE(globe.value().globe(), nullptr);
    for (std::size_t i = 0; i < poses.size(); ++i) {
        const GlobePose p = globe.value().globe()->poseAt(globeSamples[i].timeS);
        EXPECT_NEAR(p.where.latitudeDeg, poses[i].where.latitudeDeg, 1e-7);
        EXPECT_NEAR(p.where.longitudeDeg, poses[i].where.longitudeDeg, 1e-7);
        EXPECT_NEAR(p.where.height, poses[i].where.height, 1e-3);
        EXPECT_NEAR(p.headingDeg, poses[i].headingDeg, 1e-6);
        EXPECT_NEAR(p.pitchDeg, poses[i].pitchDeg, 1e-6);
    }

    // Times out of order are refused as fromKeyframes refuses them.
    std::swap(samples[0], samples[2]);
    auto refused = FlightPath::fromCameras(PathFrame::Plane, samples);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().message.find("times must increase strictly"), std::string::npos);
}

}  // namespace
}  // namespace terrain::runtime
