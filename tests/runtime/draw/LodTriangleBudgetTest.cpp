// Model no more than a scene needs (issue 6): on settled views, triangles drop
// monotonically as ε grows; a flat plain collapses to its root patch, because Err(P) = 0
// never splits it, drawn with the fewest triangles the method has: one coarse cell of two
// triangles and a skirt of two on each side (CoarseCells.h), or, as blocks, every one of
// its K² tessellation blocks at factor 1 and its 4K skirt segments, two triangles each
// (Yusov's fixed K × K blocks per patch); and in a DEM that is flat but for one hill,
// every drawn patch that is flat is one cell, and no flat patch is split.
#include "AccuracyScenes.h"
#include "GlTestFixture.h"
#include "TempFolder.h"
#include "TerrainViewChecks.h"
#include "terrain/source/ProceduralDems.h"
#include "terrain/source/DemReader.h"
#include "terrain/pyramid/PyramidReader.h"
#include "terrain/runtime/EdgeTessellation.h"
#include "terrain/runtime/TerrainSession.h"

#include <epoxy/gl.h>

#include <array>
#include <cmath>
#include <iostream>
#include <random>
#include <span>
#include <string>

namespace terrain::test {
namespace {

constexpr int kWidth = 256;
constexpr int kHeight = 192;

/// Triangles of a patch that is the whole DEM drawn as blocks at their minimum: 2 per block
/// (K²); no skirt, since its four edges are the DEM's own (skirtAlongSurfaceEdge: no patch
/// lies beyond them to crack against).
std::uint64_t minimumBlockTriangles(const io::PyramidLayout& layout) {
    const auto k = static_cast<std::uint64_t>(layout.blocksPerSide());
    return 2 * k * k;
}

/// Triangles of a patch that is the whole DEM drawn as a single coarse cell
/// (CoarseCells.h): 2, and no skirt (as above).
constexpr std::uint64_t kOneCellTriangles = 2;

/// Whether the K² + 4K records of a patch are one coarse cell: block 0 and the first skirt
/// of each side at factor 1, every other primitive merged into them.
void expectOneCell(std::span<const runtime::RecordedTessFactors> records, int k,
                   const std::string& what) {
    for (int p = 0; p < k * k + 4 * k; ++p) {
        const runtime::RecordedTessFactors& f = records[static_cast<std::size_t>(p)];
        const bool drawsCell = p == 0 || (p >= k * k && (p - k * k) % k == 0);
        EXPECT_EQ(f.merged(), !drawsCell) << what << ", primitive " << p;
        if (!drawsCell) continue;
        EXPECT_EQ(f.outer, (std::array<std::int32_t, 4>{1, 1, 1, 1}))
            << what << ", primitive " << p;
        EXPECT_EQ(f.inner, (std::array<std::int32_t, 2>{1, 1})) << what << ", primitive " << p;
    }
}

/// Settles a fresh session for `camera` at ε (both stages) and draws once, measured.
struct DrawnView {
    std::uint64_t triangles = 0;
    std::vector<runtime::PatchDraw> patches;
    std::vector<runtime::RecordedTessFactors> factors;
};

DrawnView drawSettled(const std::filesystem::path& pyramid, const runtime::Camera& camera,
                      double errorPx, bool cullBlocks, bool recordFactors = false,
                      bool coarseCells = true) {
    runtime::TerrainSessionOptions options = roomySessionOptions(errorPx);
    options.renderer.recordTessFactors = recordFactors;
    auto opened = runtime::TerrainSession::open(pyramid, options);
    EXPECT_TRUE(opened) << opened.error().message;
    if (!opened) return {};
    runtime::TerrainSession& session = *opened.value();
    EXPECT_TRUE(session.settle(camera, std::chrono::seconds(60)));
    session.beginFrame(camera);
    auto fb = gl::Framebuffer::create(kWidth, kHeight);
    EXPECT_TRUE(fb) << fb.error().message;
    runtime::TerrainStyle style;
    style.measure = true;
    style.cullBlocks = cullBlocks;
    style.coarseCells = coarseCells;
    fb.value().clear(kHoleColor, 0.0f);
    glBindFramebuffer(GL_FRAMEBUFFER, fb.value().id());
    glViewport(0, 0, kWidth, kHeight);
    DrawnView view;
    view.triangles = session.draw(camera, style).triangles;
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    view.patches.assign(session.draws().begin(), session.draws().end());
    if (recordFactors) {
        view.factors = session.renderer().readTessFactors(static_cast<int>(view.patches.size()));
    }
    runtime::FrameTelemetry t;
    session.endFrame(t);
    EXPECT_TRUE(session.streamer().drain(std::chrono::seconds(10)));
    return view;
}

class LodTriangleBudgetTest : public GlTest {};

TEST_F(LodTriangleBudgetTest, TrianglesDropMonotonicallyAsTheThresholdGrows) {
    const TempFolder folder;
    auto reader = io::openProceduralDem("procedural:size=513,seed=3");
    ASSERT_TRUE(reader) << reader.error().message;
    const std::filesystem::path pyramid = buildScenePyramid(*reader.value(), folder, "procedural");
    auto surface = runtime::FullResolutionSurface::open(pyramid);
    ASSERT_TRUE(surface) << surface.error().message;
    const runtime::TerrainGeometry& g = surface.value().geometry();
    std::mt19937_64 random(31);
    const std::vector<runtime::Camera> poses = {
        groundPose(surface.value(), kWidth, kHeight, 0.25, 0.5, 80.0, -3.0, 2.0),
        groundPose(surface.value(), kWidth, kHeight, 0.6, 0.3, 200.0, -15.0, 300.0),
        wholeTerrainPose(g, kWidth, kHeight),
        randomFullView(g, kWidth, kHeight, random),
    };
    const std::vector<double> thresholds{0.5, 1.0, 2.0, 4.0, 8.0, 16.0};
    for (std::size_t p = 0; p < poses.size(); ++p) {
        std::string line;
        std::uint64_t previous = std::numeric_limits<std::uint64_t>::max();
        std::uint64_t first = 0, last = 0;
        for (const double errorPx : thresholds) {
            // A fresh session per ε: a tree refined for another ε would keep its history
            // (merges wait for ε / hysteresis).
            const DrawnView view = drawSettled(pyramid, poses[p], errorPx, true);
            line += " " + std::to_string(view.triangles);
            EXPECT_LE(view.triangles, previous) << "pose " << p << " (" << describe(poses[p])
                                                << "): more triangles at ε = " << errorPx;
            previous = view.triangles;
            if (errorPx == thresholds.front()) first = view.triangles;
            last = view.triangles;
        }
        std::cout << "[          ] pose " << p << ", triangles at ε = 0.5 … 16 px:" << line << "\n";
        EXPECT_LT(last * 4, first) << "pose " << p << ": ε from 0.5 to 16 px must cut triangles";
    }
}

TEST_F(LodTriangleBudgetTest, FlatPlainIsOnePatchOfMinimumTriangles) {
    FunctionDem dem(
        257, 257, 30.0, [](std::int64_t, std::int64_t) { return 250.0f; }, false);
    const TempFolder folder;
    const std::filesystem::path pyramid = buildScenePyramid(dem, folder, "flat");
    auto reader = io::PyramidReader::open(pyramid);
    ASSERT_TRUE(reader) << reader.error().message;
    auto root = reader.value().readPatch({0, 0, 0});
    ASSERT_TRUE(root) << root.error().message;
    EXPECT_EQ(root.value().info.error, 0.0f);
    auto surface = runtime::FullResolutionSurface::open(pyramid);
    ASSERT_TRUE(surface) << surface.error().message;
    const runtime::TerrainGeometry& g = surface.value().geometry();
    const io::PyramidLayout& layout = g.layout();
    ASSERT_GT(layout.levelCount(), 2) << "the plain must have levels to (not) split into";
    const int k = layout.blocksPerSide();
    const std::uint64_t minimum = minimumBlockTriangles(layout);
    const std::vector<runtime::Camera> poses = {
        wholeTerrainPose(g, kWidth, kHeight),
        groundPose(surface.value(), kWidth, kHeight, 0.1, 0.9, 45.0, -30.0, 50.0),
        groundPose(surface.value(), kWidth, kHeight, 0.5, 0.5, 30.0, 0.0, 1.0),
    };
    auto probe = runtime::AccuracyProbe::create(pyramid, {.widthPx = kWidth, .heightPx = kHeight});
    ASSERT_TRUE(probe) << probe.error().message;
    for (const runtime::Camera& camera : poses) {
        for (const double errorPx : {0.5, 1.0, 4.0}) {
            const std::string what = describe(camera) + " at ε = " + std::to_string(errorPx);
            const DrawnView blocks = drawSettled(pyramid, camera, errorPx, false, true, false);
            ASSERT_EQ(blocks.patches.size(), 1u) << what;
            EXPECT_EQ(blocks.patches.front().id.level, 0)
                << what << ": a flat patch (Err(P) = 0) was split";
            ASSERT_EQ(blocks.factors.size(), static_cast<std::size_t>(k * k + 4 * k));
            // As blocks, every block edge of the plain is simplified to factor 1, wherever
            // it lies — also behind the camera, where an error of 0 projects to nothing.
            for (int b = 0; b < k * k; ++b) {
                const runtime::RecordedTessFactors& f = blocks.factors[static_cast<std::size_t>(b)];
                for (int e = 0; e < 4; ++e) {
                    EXPECT_EQ(f.outer[static_cast<std::size_t>(e)], 1)
                        << what << ", block " << b << " edge " << e;
                }
            }
            // Without block culling the count is the formula's exactly.
            EXPECT_EQ(blocks.triangles, minimum) << what;
            // With coarse cells (the default) the plain is one cell: its bound is 0.
            const DrawnView all = drawSettled(pyramid, camera, errorPx, false, true);
            ASSERT_EQ(all.factors.size(), static_cast<std::size_t>(k * k + 4 * k));
            expectOneCell(all.factors, k, what);
            EXPECT_EQ(all.triangles, kOneCellTriangles) << what;
            // Block culling only ever removes primitives.
            const DrawnView culled = drawSettled(pyramid, camera, errorPx, true);
            EXPECT_LE(culled.triangles, all.triangles) << what;
            EXPECT_GT(culled.triangles, 0u) << what;
            std::cout << "[          ] " << what << ": " << blocks.triangles
                      << " triangles as blocks, " << all.triangles << " as one cell ("
                      << culled.triangles << " with block culling)\n";
        }
        // And it is exact: no error, no crack.
        auto session = runtime::TerrainSession::open(pyramid, roomySessionOptions(1.0));
        ASSERT_TRUE(session) << session.error().message;
        const SettledMeasure m = measureSettled(*session.value(), *probe.value(), camera, 1.0);
        EXPECT_TRUE(m.accuracy.finite());
        EXPECT_LE(m.accuracy.error.maxPx, kRasterTolerancePx)
            << describe(camera) << ": " << describe(m.accuracy);
        EXPECT_EQ(m.accuracy.crackPixels(), 0u);
        EXPECT_GT(m.accuracy.image.psnrDb, 40.0) << describe(camera);
    }
    std::cout << "[          ] flat plain: 1 patch, as blocks at least " << minimum
              << " triangles (2·K², K = " << k << "), as one cell " << kOneCellTriangles << "\n";
}

TEST_F(LodTriangleBudgetTest, FlatPatchesOfABumpyDemGetTheMinimum) {
    // Flat at 100 m but for one hill in the north-west corner: the coarse LOD splits
    // towards the hill only, and every drawn flat patch (Err(P) = 0, every λ(d) = 0) is
    // one coarse cell at factor 1.
    FunctionDem dem(
        513, 513, 30.0,
        [](std::int64_t x, std::int64_t y) {
            const double r =
                std::hypot(static_cast<double>(x) - 60.0, static_cast<double>(y) - 60.0);
            return static_cast<float>(100.0 +
                                      (r < 40.0 ? 300.0 * std::cos(r / 40.0 * 1.5707963) : 0.0));
        },
        false);
    const TempFolder folder;
    const std::filesystem::path pyramid = buildScenePyramid(dem, folder, "bump");
    auto reader = io::PyramidReader::open(pyramid);
    ASSERT_TRUE(reader) << reader.error().message;
    auto surface = runtime::FullResolutionSurface::open(pyramid);
    ASSERT_TRUE(surface) << surface.error().message;
    const runtime::TerrainGeometry& g = surface.value().geometry();
    const int k = g.layout().blocksPerSide();
    const int perInstance = k * k + 4 * k;
    // From above the hill, looking across the plain.
    const glm::dvec2 hill = g.worldOfSample(60.0, 60.0);
    const runtime::Camera camera =
        lookingAt(kWidth, kHeight, {hill - glm::dvec2(300.0, -300.0), 700.0},
                  {g.worldAtFraction(0.7, 0.7), 100.0});
    const DrawnView view = drawSettled(pyramid, camera, 1.0, false, true);
    ASSERT_EQ(view.factors.size(), view.patches.size() * static_cast<std::size_t>(perInstance));
    int flatPatches = 0, bumpyPatches = 0;
    for (std::size_t i = 0; i < view.patches.size(); ++i) {
        const io::PatchId id = view.patches[i].id;
        auto info = reader.value().patchInfo(id);
        ASSERT_TRUE(info) << info.error().message;
        if (id.level > 0) {
            // The parent was split, so it was not flat.
            auto parent = reader.value().patchInfo({id.level - 1, id.x / 2, id.y / 2});
            ASSERT_TRUE(parent) << parent.error().message;
            EXPECT_GT(parent.value().error, 0.0f)
                << "a flat patch was split: level " << id.level - 1;
        }
        if (info.value().maxHeight != info.value().minHeight) {
            ++bumpyPatches;
            continue;
        }
        ++flatPatches;
        EXPECT_EQ(info.value().error, 0.0f);
        // Every λ(d) and Err(P) is 0, so every cell bound is too: the patch is one cell.
        expectOneCell(std::span(view.factors)
                          .subspan(i * static_cast<std::size_t>(perInstance),
                                   static_cast<std::size_t>(perInstance)),
                      k, "flat patch level " + std::to_string(id.level));
    }
    std::cout << "[          ] " << flatPatches << " flat and " << bumpyPatches
              << " bumpy patches drawn, " << view.triangles << " triangles\n";
    EXPECT_GT(flatPatches, 3);
    EXPECT_GT(bumpyPatches, 0);
}

}  // namespace
}  // namespace terrain::test
