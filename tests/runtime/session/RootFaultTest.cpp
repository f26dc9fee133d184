// A fault no frame can draw around (issue 16): when a root patch cannot be read there is no
// ancestor to draw in its place, so the session says so (fatalFault names the shard) and
// settle() stops at once instead of waiting out its timeout. Any other failed patch is not
// fatal: its ancestor draws the area and settle() still succeeds. No clock is read: settle()
// is given a day, which only a settle that waits for nothing would spend (ctest's timeout
// then fails the test).
#include "GeographicFunctionDem.h"
#include "GlTestFixture.h"
#include "StreamingTestPyramid.h"
#include "TempFolder.h"
#include "TestCameras.h"
#include "terrain/globe/CubeSphere.h"
#include "terrain/pyramid/GlobeLayout.h"
#include "terrain/build/GlobePyramidBuilder.h"
#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/runtime/GlobeCamera.h"
#include "terrain/runtime/PlaneSurface.h"
#include "terrain/runtime/TerrainGeometry.h"
#include "terrain/runtime/TerrainSession.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>

namespace terrain::runtime {
namespace {

namespace fs = std::filesystem;
// Longer than any run: a settle() that returns false before it has returned for the fault.
constexpr auto kTimeout = std::chrono::hours(24);

// A copy of `pyramid` in `folder` whose shard holding `patch` is bytes that are not a shard.
fs::path damagedCopy(const fs::path& pyramid, const test::TempFolder& folder,
                     const io::PatchId& patch) {
    const fs::path copy = folder.path() / "damaged.pyramid";
    fs::copy(pyramid, copy, fs::copy_options::recursive);
    auto manifest = io::readManifest(copy);
    EXPECT_TRUE(manifest) << manifest.error().message;
    const io::PyramidLayout& layout = manifest.value().layout;
    const fs::path shard = copy / layout.shardPath(layout.shardOf(patch));
    EXPECT_TRUE(fs::exists(shard)) << shard;
    std::ofstream(shard, std::ios::trunc | std::ios::binary) << "not an OpenEXR shard\n";
    return copy;
}

// High over the middle of the DEM, the whole of it in view.
Camera planarCamera(const TerrainSession& session) {
    const TerrainGeometry& g = planeGeometry(session.surface());
    return test::cameraOverDem(g, 0.5, 0.3, 0.4 * g.demSize().x, 0.5, 0.6);
}

class RootFaultTest : public test::GlTest {};

TEST_F(RootFaultTest, UnreadableRootIsFatalAndSettleDoesNotWait) {
    test::TempFolder folder;
    const fs::path damaged =
        damagedCopy(test::streamingTestPyramid(), folder, io::PatchId{0, 0, 0});
    auto opened = TerrainSession::open(damaged, {});
    ASSERT_TRUE(opened) << opened.error().message;
    TerrainSession& session = *opened.value();
    const Camera camera = planarCamera(session);
    EXPECT_FALSE(session.settle(camera, kTimeout));
    const TileFault* fatal = session.fatalFault();
    ASSERT_NE(fatal, nullptr);
    EXPECT_EQ(fatal->id, (io::PatchId{0, 0, 0}));
    EXPECT_NE(fatal->message.find("0.exr"), std::string::npos) << fatal->message;
    EXPECT_TRUE(session.draws().empty());
}

TEST_F(RootFaultTest, UnreadableChildIsDrawnByTheRoot) {
    test::TempFolder folder;
    const fs::path damaged =
        damagedCopy(test::streamingTestPyramid(), folder, io::PatchId{1, 0, 0});
    auto opened = TerrainSession::open(damaged, {});
    ASSERT_TRUE(opened) << opened.error().message;
    TerrainSession& session = *opened.value();
    const Camera camera = planarCamera(session);
    EXPECT_TRUE(session.settle(camera, kTimeout));
    EXPECT_EQ(session.fatalFault(), nullptr);
    EXPECT_FALSE(session.streamer().faults().empty()) << "the view needs the damaged patch";
    EXPECT_FALSE(session.draws().empty());
}

TEST_F(RootFaultTest, UnreadableCubeFaceRootIsFatalOnTheGlobe) {
    test::TempFolder folder;
    // A coarse planet, sparse nowhere: every face root exists.
    test::GeographicFunctionDem source(
        -180.0, 90.0, 360, 180, 1.0, 1.0, [](double latitude, double longitude) {
            return static_cast<float>(500.0 * std::sin(0.1 * latitude) *
                                      std::cos(0.05 * longitude));
        });
    io::PyramidBuildOptions options;
    options.patchSamples = 33;
    options.blockQuads = 8;
    options.shardPatches = 8;
    options.threads = 2;
    const fs::path pyramid = folder.path() / "planet.pyramid";
    auto built = io::buildGlobePyramid(source, pyramid, options);
    ASSERT_TRUE(built) << built.error().message;

    // Straight down from orbit at (20°N, 30°E): the root of the face under the camera.
    constexpr double kLatitude = 20.0, kLongitude = 30.0, kDegree = 3.14159265358979 / 180.0;
    const int face =
        globe::facePointOf({std::cos(kLatitude * kDegree) * std::cos(kLongitude * kDegree),
                            std::cos(kLatitude * kDegree) * std::sin(kLongitude * kDegree),
                            std::sin(kLatitude * kDegree)})
            .face;
    const io::PatchId faceRoot = io::layoutPatchOf(globe::GlobePatchId{face, 0, 0, 0});
    test::TempFolder damagedFolder;
    const fs::path damaged = damagedCopy(pyramid, damagedFolder, faceRoot);
    auto opened = TerrainSession::open(damaged, {});
    ASSERT_TRUE(opened) << opened.error().message;
    TerrainSession& session = *opened.value();
    Camera camera;
    camera.viewportWidth = 160;
    camera.viewportHeight = 120;
    placeOnGlobe(camera, GlobePose{{kLatitude, kLongitude, 20e6}, 0.0, -90.0});
    EXPECT_FALSE(session.settle(camera, kTimeout));
    const TileFault* fatal = session.fatalFault();
    ASSERT_NE(fatal, nullptr);
    EXPECT_EQ(fatal->id, faceRoot);
    EXPECT_NE(fatal->message.find(".exr"), std::string::npos) << fatal->message;
}

}  // namespace
}  // namespace terrain::runtime
