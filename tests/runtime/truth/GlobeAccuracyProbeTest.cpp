// The accuracy probe on the globe (AccuracyProbe::create with a GlobeReferenceScene and two
// GlobeTruths): a settled frame of a globe session is measured against the sources (the
// error) and the pyramid's finest level (lodError), within ε; the LOD leaves no crack
// against the globe reference image, which it resembles; and a partial reference image is
// not compared.
#include "AccuracyScenes.h"
#include "GlTestFixture.h"
#include "GlobeTestSources.h"
#include "TempFolder.h"
#include "terrain/build/GlobeSourceSurface.h"
#include "terrain/pyramid/GlobeGroundHeight.h"
#include "terrain/pyramid/PyramidReader.h"
#include "terrain/runtime/AccuracyProbe.h"
#include "terrain/runtime/GlobeCamera.h"
#include "terrain/runtime/GlobeReferenceScene.h"
#include "terrain/runtime/GlobeTruth.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <memory>
#include <string>

namespace terrain::test {
namespace {

constexpr int kWidth = 200;
constexpr int kHeight = 120;

class GlobeAccuracyProbeTest : public GlTest {
protected:
    static void SetUpTestSuite() {
        GlTest::SetUpTestSuite();
        s_folder = std::make_unique<TempFolder>();
        s_pyramid = s_folder->path() / "planet.pyramid";
        auto built = buildReliefPlanet(s_pyramid);
        ASSERT_TRUE(built) << built.error().message;
    }
    static void TearDownTestSuite() {
        s_folder.reset();
        GlTest::TearDownTestSuite();
    }

    // A probe of the pyramid's reference scene against `truths`.
    static Result<std::unique_ptr<runtime::AccuracyProbe>> probeOf(
        io::PyramidReader& pyramid, std::vector<std::unique_ptr<runtime::TruthSurface>> truths) {
        return runtime::AccuracyProbe::create(
            std::make_unique<runtime::GlobeReferenceScene>(pyramid), std::move(truths),
            {.widthPx = kWidth, .heightPx = kHeight});
    }
    // A session with room for every patch of the planet, at ε = `errorPx`.
    static Result<std::unique_ptr<runtime::TerrainSession>> openSession(double errorPx) {
        runtime::TerrainSessionOptions options;
        options.streaming.gpuLayers = 1024;
        options.lod.errorPx = errorPx;
        return runtime::TerrainSession::open(s_pyramid, options);
    }

    static inline std::unique_ptr<TempFolder> s_folder;
    static inline std::filesystem::path s_pyramid;
};

runtime::Camera cameraAt(const runtime::GlobePose& pose) {
    runtime::Camera camera;
    camera.viewportWidth = kWidth;
    camera.viewportHeight = kHeight;
    runtime::placeOnGlobe(camera, pose);
    return camera;
}

TEST_F(GlobeAccuracyProbeTest, MeasuresAGlobeFrameAgainstItsSourcesAndItsFinestLevel) {
    GeographicFunctionDem source(-180.0, 90.0, 720, 360, 0.5, 0.5, reliefPlanet);
    io::DemReader* const sources[] = {&source};
    auto surface = io::GlobeSourceSurface::read(sources, std::uint64_t{1} << 30, 32);
    ASSERT_TRUE(surface) << surface.error().message;
    auto finest = io::GlobeGroundQuery::open(s_pyramid);
    ASSERT_TRUE(finest) << finest.error().message;
    auto pyramid = io::PyramidReader::open(s_pyramid);
    ASSERT_TRUE(pyramid) << pyramid.error().message;
    std::vector<std::unique_ptr<runtime::TruthSurface>> truths;
    truths.push_back(std::make_unique<runtime::GlobeTruth>(
        [&surface](double latitude, double longitude) -> Result<std::pair<double, double>> {
            return surface.value().heightsAt(latitude, longitude);
        }));
    truths.push_back(
        std::make_unique<runtime::GlobeTruth>([&finest](double latitude, double longitude) {
            return finest.value().heightsAt(latitude, longitude);
        }));
    auto probe = probeOf(pyramid.value(), std::move(truths));
    ASSERT_TRUE(probe) << probe.error().message;

    auto session = openSession(2.0);
    ASSERT_TRUE(session) << session.error().message;
    constexpr double kRasterTolerancePx = 0.05;
    for (const auto& [name, pose] :
         {std::pair{"oblique from 1,000 km", runtime::GlobePose{{40.0, 10.0, 1e6}, 0.0, -20.0}},
          std::pair{"over a cube corner", runtime::GlobePose{{35.26439, 45.0, 20e3}, 30.0, -45.0}},
          std::pair{"across the antimeridian",
                    runtime::GlobePose{{0.0, 179.99, 8e3}, 90.0, -30.0}}}) {
        SCOPED_TRACE(name);
        const runtime::Camera camera = cameraAt(pose);
        const SettledMeasure m =
            measureSettledFrame(*session.value(), *probe.value(), camera, measuredStyle());
        const runtime::FrameAccuracy& a = m.accuracy;
        std::cout << name << ": error max " << a.error.maxPx << " px over " << a.error.pixels
                  << " pixels, the LOD's own " << (a.lodError ? a.lodError->maxPx : -1.0)
                  << " px, PSNR " << a.image.psnrDb << " dB, " << a.crackPixels() << " cracks\n";
        EXPECT_TRUE(a.comparedWithReference);
        EXPECT_GT(a.error.pixels, static_cast<std::uint64_t>(kWidth * kHeight / 4));
        EXPECT_LE(a.error.maxPx, 2.0 + kRasterTolerancePx);
        ASSERT_TRUE(a.lodError.has_value());
        EXPECT_EQ(a.lodError->pixels, a.error.pixels);
        EXPECT_LE(a.lodError->maxPx, 2.0 + kRasterTolerancePx);
        EXPECT_EQ(a.crackPixels(), 0u);
        EXPECT_GT(a.referencePixels, 0u);
        EXPECT_GE(a.image.psnrDb, 25.0);
        EXPECT_TRUE(a.finite());
    }
}

TEST_F(GlobeAccuracyProbeTest, APartialReferenceImageIsNotCompared) {
    auto pyramid = io::PyramidReader::open(s_pyramid);
    ASSERT_TRUE(pyramid) << pyramid.error().message;
    std::vector<std::unique_ptr<runtime::TruthSurface>> truths;
    truths.push_back(std::make_unique<runtime::GlobeTruth>(
        [](double latitude, double longitude) -> Result<std::pair<double, double>> {
            const double h = reliefPlanet(latitude, longitude);
            return std::pair{h, h};
        }));
    auto probe = probeOf(pyramid.value(), std::move(truths));
    ASSERT_TRUE(probe) << probe.error().message;
    auto session = openSession(2.0);
    ASSERT_TRUE(session) << session.error().message;
    const runtime::Camera camera = cameraAt({{40.0, 10.0, 1e6}, 0.0, -20.0});
    ASSERT_TRUE(session.value()->settle(camera, std::chrono::seconds(60)));
    session.value()->beginFrame(camera);
    const runtime::LodCapture lod =
        probe.value()->captureLod(*session.value(), camera, measuredStyle());
    runtime::FrameTelemetry ignored;
    session.value()->endFrame(ignored);
    auto reference = probe.value()->renderReference(camera, {});
    ASSERT_TRUE(reference) << reference.error().message;
    ASSERT_TRUE(reference.value().draw.complete);
    auto whole = probe.value()->compare(camera, lod, reference.value(), 2.0);
    ASSERT_TRUE(whole) << whole.error().message;
    EXPECT_TRUE(whole.value().comparedWithReference);
    EXPECT_GT(whole.value().referencePixels, 0u);

    runtime::ReferenceCapture partial = reference.value();
    partial.draw.complete = false;
    auto measured = probe.value()->compare(camera, lod, partial, 2.0, &lod, &reference.value());
    ASSERT_TRUE(measured) << measured.error().message;
    const runtime::FrameAccuracy& a = measured.value();
    EXPECT_FALSE(a.comparedWithReference);
    EXPECT_EQ(a.referencePixels, 0u);
    EXPECT_EQ(a.crackPixels() + a.uncoveredPixels, 0u);
    EXPECT_TRUE(std::isnan(a.poppingLevels));
    EXPECT_FALSE(a.lodError.has_value()) << "one truth: no lodError";
    // The error is still measured, over every drawn pixel rather than those the reference
    // also drew.
    EXPECT_GE(a.error.pixels, whole.value().error.pixels);
    EXPECT_GT(a.error.pixels, 0u);
    EXPECT_TRUE(a.finite());
}

}  // namespace
}  // namespace terrain::test
