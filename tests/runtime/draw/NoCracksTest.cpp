// No cracks (Yusov & Shevtsov 2011, §5): for random camera poses whose whole view is
// terrain, stream until the view settles (patches of mixed levels, error-driven block
// factors), render with skirts over a clear colour the terrain never produces (pure
// magenta, no fog), and count clear-colour pixels: there must be none. The control renders
// the same frames without skirts and must show some, which proves the test can fail.
#include "GlTestFixture.h"
#include "SharedData.h"
#include "StreamingTestPyramid.h"
#include "TempFolder.h"
#include "TerrainViewChecks.h"
#include "terrain/build/PyramidBuilder.h"
#include "terrain/dem/OpenDem.h"
#include "terrain/gl/Framebuffer.h"
#include "terrain/runtime/PatchSelection.h"
#include "terrain/runtime/PlaneSurface.h"
#include "terrain/runtime/SkirtDepth.h"
#include "terrain/runtime/TerrainGeometry.h"
#include "terrain/runtime/TerrainRenderer.h"
#include "terrain/runtime/TileStreamer.h"
#include "terrain/source/DemReader.h"

#include <epoxy/gl.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <iostream>
#include <numbers>
#include <random>
#include <string>
#include <vector>

namespace terrain::test {
namespace {

using runtime::Camera;

constexpr int kWidth = 320;
constexpr int kHeight = 240;
constexpr double kFineErrorPx = 2.0;  // fine LOD (block edges)

struct CrackStats {
    int poses = 0;
    int mixedLevelPoses = 0;  ///< poses drawing patches of two levels or more
    std::uint64_t patchesDrawn = 0;
    std::uint64_t clearPixelsWithSkirts = 0;
    int posesWithClearPixelsWithSkirts = 0;
    std::uint64_t clearPixelsWithoutSkirts = 0;
    int posesWithCracksWithoutSkirts = 0;
    std::uint64_t worstPoseWithoutSkirts = 0;
};

class NoCracksTest : public GlTest {
protected:
    /// The coarse LOD's ε (patches) of each pose is drawn log-uniformly from
    /// [minSelectionPx, maxSelectionPx]: a range over which most views mix levels.
    static CrackStats run(const std::filesystem::path& pyramid, double minSelectionPx,
                          double maxSelectionPx, int poses, std::uint64_t seed) {
        runtime::TileStreamerOptions o;
        o.gpuLayers = 512;                         // holds every patch of these pyramids
        o.cpuCacheBytes = std::size_t{256} << 20;  // likewise
        o.uploadBytesPerFrame = std::size_t{64} << 20;
        auto opened = runtime::TileStreamer::open(pyramid, o);
        EXPECT_TRUE(opened) << opened.error().message;
        if (!opened) return {};
        runtime::TileStreamer& streamer = *opened.value();
        const runtime::PlaneSurface surface(streamer.manifest());
        const runtime::TerrainGeometry& g = surface.geometry();
        auto renderer = runtime::TerrainRenderer::create(surface, o.gpuLayers);
        EXPECT_TRUE(renderer) << renderer.error().message;
        auto fb = gl::Framebuffer::create(kWidth, kHeight);
        EXPECT_TRUE(fb) << fb.error().message;
        if (!renderer || !fb) return {};

        std::mt19937_64 random(seed);
        std::vector<runtime::PatchDraw> draws;
        CrackStats stats;
        for (int pose = 0; pose < poses; ++pose) {
            const Camera camera = randomFullView(g, kWidth, kHeight, random);
            const double selectionErrorPx =
                minSelectionPx * std::pow(maxSelectionPx / minSelectionPx,
                                          std::uniform_real_distribution<double>(0.0, 1.0)(random));
            // Stream until the view settles: every wanted patch resident, nothing waiting.
            bool settled = false;
            for (int frame = 0; frame < 5000 && !settled; ++frame) {
                streamer.beginFrame();
                const runtime::PatchSelectionStats s =
                    runtime::selectPatches(camera, g, selectionErrorPx, streamer, draws);
                runtime::FrameTelemetry telemetry;
                streamer.endFrame(telemetry);
                settled =
                    !draws.empty() && s.waitingSplits == 0 && streamer.loadsOutstanding() == 0;
                if (!settled) streamer.waitForReads(std::chrono::milliseconds(100));
            }
            EXPECT_TRUE(settled) << "pose " << pose << " never settled";
            runtime::assignSkirtDepths(draws, streamer.pool());
            const auto [lowest, highest] = std::minmax_element(
                draws.begin(), draws.end(),
                [](const auto& a, const auto& b) { return a.id.level < b.id.level; });
            stats.mixedLevelPoses += lowest->id.level != highest->id.level ? 1 : 0;
            stats.patchesDrawn += draws.size();

            runtime::TerrainStyle style;
            style.fogDensityPerM = 0.0f;
            glBindFramebuffer(GL_FRAMEBUFFER, fb.value().id());
            glViewport(0, 0, kWidth, kHeight);
            for (const bool skirts : {true, false}) {
                style.skirts = skirts;
                fb.value().clear(kHoleColor, 0.0f);
                renderer.value().draw(camera, streamer.pool(), draws, style, kFineErrorPx);
                const std::uint64_t clear = countHolePixels(fb.value());
                if (skirts) {
                    stats.clearPixelsWithSkirts += clear;
                    stats.posesWithClearPixelsWithSkirts += clear > 0 ? 1 : 0;
                    EXPECT_EQ(clear, 0u)
                        << "pose " << pose << ": position (" << camera.position.x << ", "
                        << camera.position.y << ", " << camera.position.z << "), yaw " << camera.yaw
                        << ", pitch " << camera.pitch << ", " << draws.size() << " patches, levels "
                        << lowest->id.level << "–" << highest->id.level;
                } else {
                    stats.clearPixelsWithoutSkirts += clear;
                    stats.posesWithCracksWithoutSkirts += clear > 0 ? 1 : 0;
                    stats.worstPoseWithoutSkirts = std::max(stats.worstPoseWithoutSkirts, clear);
                }
            }
            glBindFramebuffer(GL_FRAMEBUFFER, 0);
            ++stats.poses;
        }
        EXPECT_TRUE(streamer.drain(std::chrono::seconds(10)));
        return stats;
    }

    static void report(const std::string& name, const CrackStats& s) {
        std::cout << "[          ] " << name << ": " << s.poses << " poses (" << s.mixedLevelPoses
                  << " with mixed levels, " << s.patchesDrawn << " patches drawn); with skirts "
                  << s.clearPixelsWithSkirts << " clear pixels; without skirts "
                  << s.clearPixelsWithoutSkirts << " clear pixels in "
                  << s.posesWithCracksWithoutSkirts << " poses (worst " << s.worstPoseWithoutSkirts
                  << ")\n";
        RecordProperty("clear_pixels_with_skirts", std::to_string(s.clearPixelsWithSkirts));
        RecordProperty("clear_pixels_without_skirts", std::to_string(s.clearPixelsWithoutSkirts));
        RecordProperty("poses_with_cracks_without_skirts",
                       std::to_string(s.posesWithCracksWithoutSkirts));
    }

    static void expectCrackFree(const CrackStats& s, int poses) {
        EXPECT_EQ(s.poses, poses);
        EXPECT_EQ(s.clearPixelsWithSkirts, 0u);
        EXPECT_GT(s.mixedLevelPoses, poses / 3) << "too few poses mix patch levels";
        // The control: without skirts the same frames do crack, so the test can fail.
        EXPECT_GT(s.posesWithCracksWithoutSkirts, 0);
    }

    /// A pyramid of a shared DEM, built into `folder`: 65-sample patches of 4 × 4 blocks of
    /// the default 16 quads, so views that are all terrain still span several patches.
    static std::filesystem::path build(const std::filesystem::path& dem,
                                       const io::DemOpenOptions& options,
                                       const TempFolder& folder) {
        auto reader = io::openDem({dem.string()}, options);
        EXPECT_TRUE(reader) << reader.error().message;
        if (!reader) return {};
        const std::filesystem::path out = folder.path() / "dem.pyramid";
        io::PyramidBuildOptions buildOptions;
        buildOptions.patchSamples = 65;
        buildOptions.blockQuads = 16;
        auto built = io::buildPyramid(*reader.value(), out, buildOptions);
        EXPECT_TRUE(built) << built.error().message;
        return out;
    }
};

TEST_F(NoCracksTest, StreamingTestPyramid) {
    constexpr int kPoses = 100;
    const CrackStats s = run(streamingTestPyramid(), 1.0, 4.0, kPoses, 1);
    report("streaming test pyramid", s);
    expectCrackFree(s, kPoses);
}

TEST_F(NoCracksTest, PugetSound) {
    TERRAIN_SHARED_DATA_OR_SKIP(dem, "puget_sound_1k.png");
    const TempFolder folder;
    io::DemOpenOptions options;  // as terrain-build --vertical-scale 0.1 --spacing 160
    options.verticalScale = 0.1;
    options.pixelSize = 160.0;
    const std::filesystem::path pyramid = build(dem, options, folder);
    ASSERT_FALSE(pyramid.empty());
    constexpr int kPoses = 100;
    const CrackStats s = run(pyramid, 2.0, 32.0, kPoses, 2);
    report("puget_sound_1k", s);
    expectCrackFree(s, kPoses);
}

TEST_F(NoCracksTest, Rainier) {
    TERRAIN_SHARED_DATA_OR_SKIP(dem, "srtm3_n46w122_rainier.tif");
    const TempFolder folder;
    const std::filesystem::path pyramid = build(dem, {}, folder);
    ASSERT_FALSE(pyramid.empty());
    constexpr int kPoses = 100;
    const CrackStats s = run(pyramid, 2.0, 32.0, kPoses, 3);
    report("srtm3_n46w122_rainier", s);
    expectCrackFree(s, kPoses);
}

}  // namespace
}  // namespace terrain::test
