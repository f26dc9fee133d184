// Measured accuracy on the real DEMs of ../shared/data (issue 6): Puget Sound (1k PNG,
// 160 m, 0.1 m units) and Mount Rainier (SRTM3, geographic, with voids), built with the
// default 129-sample patches of 8 × 8 blocks, seen from three points of the default camera
// path (its low pass, its climb, its overview) at ε = 1, 2 and 4 px. As in the stability
// suite: no cracks, no NaN; the full LOD and the coarse LOD alone within ε +
// kRasterTolerancePx (AccuracyScenes.h). terrain-bench charts the same on the whole flight.
#include "AccuracyScenes.h"
#include "GlTestFixture.h"
#include "SharedData.h"
#include "TempFolder.h"
#include "terrain/dem/OpenDem.h"
#include "terrain/source/DemReader.h"
#include "terrain/runtime/CameraPath.h"

namespace terrain::test {
namespace {

constexpr int kWidth = 256;
constexpr int kHeight = 192;
constexpr double kErrorsPx[] = {1.0, 2.0, 4.0};

class AccuracyRealDemTest : public GlTest {
protected:
    static void run(const std::filesystem::path& dem, const io::DemOpenOptions& options,
                    const std::string& name) {
        const TempFolder folder;
        auto reader = io::openDem({dem.string()}, options);
        ASSERT_TRUE(reader) << reader.error().message;
        const std::filesystem::path pyramid = buildScenePyramid(
            *reader.value(), folder, name, io::PyramidLayout::kDefaultPatchSamples,
            io::PyramidLayout::kDefaultBlockQuads);
        auto surface = runtime::FullResolutionSurface::open(pyramid);
        ASSERT_TRUE(surface) << surface.error().message;
        const runtime::CameraPath path =
            runtime::CameraPath::defaultFor(surface.value().geometry());
        std::vector<Pose> poses;
        // Three poses keep the suite small under AddressSanitizer, where llvmpipe's
        // tessellator (it allocates per draw) makes each coarse-only frame seconds long.
        for (int i = 0; i <= 2; ++i) {
            runtime::Camera camera = testCamera(kWidth, kHeight);
            const double t = path.startS() + path.durationS() * i / 2.0;
            path.apply(t, camera);
            poses.push_back({"default path at " + std::to_string(t) + " s", camera});
        }
        sweep(pyramid, poses, name, kWidth, kHeight, kErrorsPx);
    }
};

TEST_F(AccuracyRealDemTest, PugetSound) {
    TERRAIN_SHARED_DATA_OR_SKIP(dem, "puget_sound_1k.png");
    io::DemOpenOptions options;  // as terrain-build --vertical-scale 0.1 --spacing 160
    options.verticalScale = 0.1;
    options.pixelSize = 160.0;
    run(dem, options, "puget_sound_1k");
}

TEST_F(AccuracyRealDemTest, Rainier) {
    TERRAIN_SHARED_DATA_OR_SKIP(dem, "srtm3_n46w122_rainier.tif");
    run(dem, {}, "srtm3_n46w122_rainier");
}

}  // namespace
}  // namespace terrain::test
