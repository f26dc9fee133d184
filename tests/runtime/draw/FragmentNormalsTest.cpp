// Shading that does not depend on the tessellation (terrain.frag, TERRAIN_FRAGMENT_NORMALS):
// the terrain draw takes each fragment's normal from the patch's full-resolution mesh,
// blended as the reference renderer blends its vertices' normals. The same LOD shaded either
// way has the same triangles and the same measured error to the bit; at full resolution the
// fragment normals are the reference's, so that image is closer to the reference than the
// one whose normals the tessellator's own triangles interpolate.
#include "AccuracyScenes.h"
#include "terrain/runtime/PlaneSurface.h"
#include "GlTestFixture.h"
#include "TempFolder.h"

#include <cmath>
#include <iostream>
#include <numbers>

namespace terrain::test {
namespace {

constexpr int kWidth = 320;
constexpr int kHeight = 240;

class FragmentNormalsTest : public GlTest {};

TEST_F(FragmentNormalsTest, SameGeometryAndTheReferencesShadingAtFullResolution) {
    // Rolling hills: normals that vary across every block.
    FunctionDem dem(
        257, 257, 30.0,
        [](std::int64_t x, std::int64_t y) {
            const double fx = static_cast<double>(x), fy = static_cast<double>(y);
            return static_cast<float>(300.0 + 90.0 * std::sin(fx / 11.0) * std::cos(fy / 17.0) +
                                      40.0 * std::sin((fx + fy) / 7.0));
        },
        false);
    const TempFolder folder;
    const std::filesystem::path pyramid = buildScenePyramid(dem, folder, "hills");
    auto probe = runtime::AccuracyProbe::create(pyramid, {.widthPx = kWidth, .heightPx = kHeight});
    ASSERT_TRUE(probe) << probe.error().message;

    struct Shaded {
        double psnrDb = 0.0;
        double errorMaxPx = 0.0;
        std::uint64_t triangles = 0;
    };
    // fixedTessFactor 0: the LOD at ε; else every block at that factor.
    const auto shade = [&](bool fragmentNormals, double errorPx, int fixedTessFactor) {
        runtime::TerrainSessionOptions options = roomySessionOptions(errorPx);
        options.renderer.fragmentNormals = fragmentNormals;
        auto session = runtime::TerrainSession::open(pyramid, options);
        EXPECT_TRUE(session) << session.error().message;
        // Looking down from low enough that every DEM cell spans several pixels.
        const runtime::TerrainGeometry& g = runtime::planeGeometry(session.value()->surface());
        const glm::dvec3 centre{g.worldAtFraction(0.5, 0.5), 300.0};
        const runtime::Camera camera =
            lookingAt(kWidth, kHeight, centre + glm::dvec3(0.0, -1.0, 1500.0), centre);
        const SettledMeasure m =
            measureSettled(*session.value(), *probe.value(), camera, errorPx, fixedTessFactor);
        return Shaded{m.accuracy.image.psnrDb, m.accuracy.error.maxPx, m.triangles};
    };
    const int fullResolution = io::PyramidLayout::kDefaultBlockQuads;
    for (const auto& [errorPx, fixed] : {std::pair{0.1, fullResolution}, {1.0, 0}, {4.0, 0}}) {
        const std::string what = "ε = " + std::to_string(errorPx) +
                                 (fixed > 0 ? ", every block at full resolution" : "");
        const Shaded vertex = shade(false, errorPx, fixed);
        const Shaded fragment = shade(true, errorPx, fixed);
        std::cout << "[          ] " << what << ": " << fragment.triangles << " triangles, PSNR "
                  << vertex.psnrDb << " dB with vertex normals, " << fragment.psnrDb
                  << " dB with fragment normals; measured error max " << fragment.errorMaxPx
                  << " px\n";
        EXPECT_EQ(fragment.triangles, vertex.triangles) << what;
        EXPECT_EQ(fragment.errorMaxPx, vertex.errorMaxPx) << what;
        if (fixed > 0) {
            EXPECT_EQ(fragment.errorMaxPx, 0.0) << what << ": not the finest level";
            EXPECT_GT(fragment.psnrDb, vertex.psnrDb + 1.0) << what;
        }
    }
}

// Where a pixel spans several samples its normal is the mean slope over its footprint, taken
// from the pyramid's level whose samples are about a footprint apart (ShadingTiles.h). Taken
// from each patch's own tile instead, the footprint's box is cut at the patch's edge, so the
// pixels along every boundary of a distant patch get the slope of part of their footprint:
// a seam of brighter and darker pixels the reference (whose tiles are cut elsewhere) lacks,
// measured as BoundaryShading's seam and as boundary artefacts.
TEST_F(FragmentNormalsTest, DistantPatchBoundariesShadeAsTheirGround) {
    // Relief at every scale, as real ground has it: octaves of ridges from 128 samples down to
    // 3, each half the height of the one before, in directions of their own.
    FunctionDem dem(
        513, 513, 10.0,
        [](std::int64_t x, std::int64_t y) {
            const double fx = static_cast<double>(x), fy = static_cast<double>(y);
            double h = 400.0, amplitude = 80.0, period = 128.0;
            for (int octave = 0; octave < 6; ++octave) {
                const double angle = 1.3 * octave + 0.4;
                h += amplitude * std::sin((std::cos(angle) * fx + std::sin(angle) * fy) *
                                              (2.0 * std::numbers::pi / period) +
                                          0.7 * octave);
                amplitude *= 0.5;
                period *= 0.5;
            }
            return static_cast<float>(h);
        },
        false);
    const TempFolder folder;
    const std::filesystem::path pyramid = buildScenePyramid(dem, folder, "ridges");
    auto probe = runtime::AccuracyProbe::create(pyramid, {.widthPx = kWidth, .heightPx = kHeight});
    ASSERT_TRUE(probe) << probe.error().message;
    auto session = runtime::TerrainSession::open(pyramid, roomySessionOptions(1.0));
    ASSERT_TRUE(session) << session.error().message;
    const runtime::TerrainGeometry& g = runtime::planeGeometry(session.value()->surface());
    double seam = 0.0;
    std::uint64_t artefacts = 0;
    int poses = 0;
    // From 5 to 9 km away, 35° to 55° down, from four sides: footprints of 2 to 10 samples.
    for (const double distanceM : {5000.0, 9000.0}) {
        for (const double pitchDeg : {35.0, 55.0}) {
            for (const double yawDeg : {0.0, 90.0, 200.0, 290.0}) {
                const double pitch = pitchDeg * std::numbers::pi / 180.0;
                const double yaw = yawDeg * std::numbers::pi / 180.0;
                const glm::dvec3 target{g.worldAtFraction(0.5, 0.5), 400.0};
                const glm::dvec3 eye =
                    target + distanceM * glm::dvec3(std::cos(pitch) * std::sin(yaw),
                                                    std::cos(pitch) * std::cos(yaw),
                                                    std::sin(pitch));
                const SettledMeasure m = measureSettled(
                    *session.value(), *probe.value(), lookingAt(kWidth, kHeight, eye, target), 1.0);
                ASSERT_TRUE(m.accuracy.boundaryShading.has_value());
                seam += m.accuracy.boundaryShading->seamLevels();
                artefacts += m.accuracy.boundaryArtefactPixels.value_or(0);
                ++poses;
            }
        }
    }
    std::cout << "[          ] " << poses << " distant poses: shading seam "
              << seam / poses << " levels a pose, " << artefacts << " boundary artefacts\n";
    // Measured: 0.22 levels and 5 artefacts (pixels on the DEM's outline and on creases), against
    // 0.39 and 12 with the box cut at each patch's edge.
    EXPECT_LT(seam / poses, 0.3);
    EXPECT_LT(artefacts, 10u);
}

}  // namespace
}  // namespace terrain::test
