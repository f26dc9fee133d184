// Native leaves (docs/globe.md, "Native leaves"): near the ground a globe session draws the
// finest detail from the sources' own grids (terrain-build --native-leaves), so its error
// against the sources stays within ε where the face grid's resampling alone exceeds it. One
// rough regional source over a smooth global one, built twice, with and without native
// grids: the same views, the error against the sources (GlobeTruth of GlobeSourceSurface)
// and the cracks (every enclosed clear pixel) of a settled frame.
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
#include <cstdint>
#include <iostream>
#include <memory>
#include <string>

namespace terrain::test {
namespace {

constexpr int kWidth = 240;
constexpr int kHeight = 135;
constexpr double kErrorPx = 2.0;
constexpr double kRasterTolerancePx = 0.05;

// Hills with ±60 m of roughness from sample to sample (a hash of the sample's place): creases
// at every sample, which a face grid laid across them cuts.
float rough(double latitude, double longitude) {
    const auto i = static_cast<std::int64_t>(std::llround(latitude * 100.0));
    const auto j = static_cast<std::int64_t>(std::llround(longitude * 100.0));
    std::uint64_t h = static_cast<std::uint64_t>(i * 73856093 ^ j * 19349663);
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdULL;
    h ^= h >> 33;
    const double noise = double(h % 2001) / 1000.0 - 1.0;  // [−1, 1]
    return hills(latitude, longitude) + static_cast<float>(60.0 * noise);
}

class NativeLeavesTest : public GlTest {
protected:
    static void SetUpTestSuite() {
        GlTest::SetUpTestSuite();
        s_folder = std::make_unique<TempFolder>();
        GeographicFunctionDem coarse(-180.0, 90.0, 180, 90, 2.0, 2.0, hills);
        GeographicFunctionDem fine(10.0, 46.0, 200, 150, 0.01, 0.01, rough);
        io::DemReader* const sources[] = {&coarse, &fine};
        io::PyramidBuildOptions options;
        options.patchSamples = 33;
        options.blockQuads = 8;
        options.shardPatches = 8;
        options.threads = 2;
        for (const bool native : {false, true}) {
            options.globeNativeLeaves = native;
            const auto path = s_folder->path() / (native ? "native.pyramid" : "face.pyramid");
            auto built = io::buildGlobePyramid(sources, path, options);
            ASSERT_TRUE(built) << built.error().message;
        }
        auto surface = io::GlobeSourceSurface::read(sources, std::uint64_t{1} << 30, 32);
        ASSERT_TRUE(surface) << surface.error().message;
        s_truth = std::make_unique<io::GlobeSourceSurface>(std::move(surface).value());
    }
    static void TearDownTestSuite() {
        s_truth.reset();
        s_folder.reset();
        GlTest::TearDownTestSuite();
    }

    struct Measured {
        runtime::FrameAccuracy accuracy;
        runtime::LodUpdateStats lod;
    };

    // A settled frame of the pyramid `name` at ε, from `pose`, against the sources.
    static Measured measure(const std::string& name, const runtime::GlobePose& pose) {
        const auto path = s_folder->path() / name;
        auto pyramid = io::PyramidReader::open(path);
        EXPECT_TRUE(pyramid) << pyramid.error().message;
        std::vector<std::unique_ptr<runtime::TruthSurface>> truths;
        truths.push_back(std::make_unique<runtime::GlobeTruth>(
            [](double latitude, double longitude) -> Result<std::pair<double, double>> {
                return s_truth->heightsAt(latitude, longitude);
            }));
        auto probe = runtime::AccuracyProbe::create(
            std::make_unique<runtime::GlobeReferenceScene>(pyramid.value()), std::move(truths),
            {.widthPx = kWidth, .heightPx = kHeight});
        EXPECT_TRUE(probe) << probe.error().message;
        runtime::TerrainSessionOptions options;
        options.streaming.gpuLayers = 1024;
        options.lod.errorPx = kErrorPx;
        auto session = runtime::TerrainSession::open(path, options);
        EXPECT_TRUE(session) << session.error().message;
        runtime::Camera camera;
        camera.viewportWidth = kWidth;
        camera.viewportHeight = kHeight;
        runtime::placeOnGlobe(camera, pose);
        const SettledMeasure m =
            measureSettledFrame(*session.value(), *probe.value(), camera, measuredStyle());
        return {m.accuracy, m.lod};
    }

    // `height` metres above the sources' surface at a place.
    static runtime::GlobePose above(double latitude, double longitude, double height,
                                    double heading, double pitch) {
        const double ground = s_truth->heightsAt(latitude, longitude).first;
        return {{latitude, longitude, ground + height}, heading, pitch};
    }

    static inline std::unique_ptr<TempFolder> s_folder;
    static inline std::unique_ptr<io::GlobeSourceSurface> s_truth;
};

TEST_F(NativeLeavesTest, NearTheGroundTheErrorAgainstTheSourcesStaysWithinEpsilon) {
    for (const auto& [name, pose] :
         {std::pair{"300 m above, looking ahead", above(45.3, 11.0, 300.0, 30.0, -20.0)},
          std::pair{"100 m above, looking down", above(45.1, 10.7, 100.0, 200.0, -45.0)}}) {
        SCOPED_TRACE(name);
        const Measured face = measure("face.pyramid", pose);
        const Measured native = measure("native.pyramid", pose);
        std::cout << name << ": against the sources, face grid only " << face.accuracy.error.maxPx
                  << " px, with native leaves " << native.accuracy.error.maxPx << " px ("
                  << native.lod.drawnNative << " native tiles of " << native.lod.drawn
                  << " draws), cracks " << face.accuracy.crackPixels() << " / "
                  << native.accuracy.crackPixels() << "\n";
        // The face grid's resampling shows: the floor the native leaves remove.
        EXPECT_GT(face.accuracy.error.maxPx, kErrorPx + kRasterTolerancePx);
        EXPECT_EQ(face.lod.drawnNative, 0u);
        EXPECT_GT(native.lod.drawnNative, 0u);
        EXPECT_TRUE(native.accuracy.comparedWithReference);
        EXPECT_LE(native.accuracy.error.maxPx, kErrorPx + kRasterTolerancePx);
        EXPECT_EQ(native.accuracy.crackPixels(), 0u);
        EXPECT_TRUE(native.accuracy.finite());
    }
}

}  // namespace
}  // namespace terrain::test
