// The stability suite (issue 6; docs/accuracy.md, "Stability suite"): the cases where LOD
// methods fail, as small scenes and camera poses, each measured against the reference
// renderer at ε = 1, 2 and 4 px after streaming settles: no cracks, no holes, no NaN, and
// the measured screen-space error within ε + kRasterTolerancePx, for the full LOD and for
// the coarse LOD alone (AccuracyScenes.h). Flat plains and triangle counts:
// LodTriangleBudgetTest; holes while streaming with full views: NoHolesWhileStreamingTest
// (teleports here add the reference's footprint, so views with sky count too). The other LOD
// methods fly the same poses, each held to what it promises (MethodSweep.h).
#include "AccuracyScenes.h"
#include "GlTestFixture.h"
#include "MethodSweep.h"
#include "TempFolder.h"
#include "TerrainViewChecks.h"
#include "terrain/pyramid/PyramidReader.h"
#include "terrain/runtime/AccuracyProbe.h"
#include "terrain/source/DemReader.h"
#include "terrain/source/ProceduralDems.h"
#include "terrain/source/ProceduralTerrain.h"

#include <cmath>
#include <iostream>
#include <random>

namespace terrain::test {
namespace {

constexpr int kWidth = 256;
constexpr int kHeight = 192;
constexpr double kErrorsPx[] = {1.0, 2.0, 4.0};
constexpr std::int64_t kProceduralSize = 513;
constexpr std::uint64_t kProceduralSeed = 3;

class AccuracyStabilityTest : public GlTest {};

TEST_F(AccuracyStabilityTest, ProceduralCliffSpikesLakeAndGrazingViews) {
    const TempFolder folder;
    const std::string spec = "procedural:size=" + std::to_string(kProceduralSize) +
                             ",seed=" + std::to_string(kProceduralSeed);
    auto reader = io::openProceduralDem(spec);
    ASSERT_TRUE(reader) << reader.error().message;
    const std::filesystem::path pyramid = buildScenePyramid(*reader.value(), folder, "procedural");
    io::ProceduralTerrainParameters parameters;
    parameters.seed = kProceduralSeed;
    parameters.widthSamples = parameters.heightSamples = kProceduralSize;
    auto terrain = io::ProceduralTerrain::create(parameters);
    ASSERT_TRUE(terrain) << terrain.error().message;
    auto surfaceOpened = runtime::FullResolutionSurface::open(pyramid);
    ASSERT_TRUE(surfaceOpened) << surfaceOpened.error().message;
    runtime::FullResolutionSurface& surface = surfaceOpened.value();
    const runtime::TerrainGeometry& g = surface.geometry();

    std::vector<Pose> poses;
    // The 1,000 m cliff, one sample wide: from its foot on the low (east) side, looking
    // west and up at it, and from above its edge looking along it.
    const std::int64_t row = kProceduralSize / 2;
    const std::int64_t column = terrain.value().cliffColumn(row);
    const glm::dvec2 cliffTop =
        g.worldOfSample(static_cast<double>(column), static_cast<double>(row));
    const double lowGround =
        groundHeightNear(surface, cliffTop.x + 40.0 * g.sampleSpacing().x, cliffTop.y);
    poses.push_back(
        {"cliff from its foot",
         lookingAt(kWidth, kHeight,
                   {cliffTop.x + 40.0 * g.sampleSpacing().x, cliffTop.y, lowGround + 30.0},
                   {cliffTop.x, cliffTop.y, lowGround + 400.0})});
    const double highGround = groundHeightNear(surface, cliffTop.x, cliffTop.y, 3);
    poses.push_back(
        {"cliff edge from above",
         lookingAt(kWidth, kHeight,
                   {cliffTop.x - 10.0 * g.sampleSpacing().x,
                    cliffTop.y - 60.0 * g.sampleSpacing().y, highGround + 150.0},
                   {cliffTop.x, cliffTop.y + 30.0 * g.sampleSpacing().y, highGround - 300.0})});
    // A single-sample spike, from 25 samples away at its own height.
    ASSERT_FALSE(terrain.value().spikes().empty());
    const io::TerrainSpike& spike = terrain.value().spikes().front();
    const glm::dvec2 spikeXY =
        g.worldOfSample(static_cast<double>(spike.x), static_cast<double>(spike.y));
    poses.push_back(
        {"spike", lookingAt(kWidth, kHeight,
                            {spikeXY.x - 25.0 * g.sampleSpacing().x,
                             spikeXY.y - 10.0 * g.sampleSpacing().y, spike.heightM + 20.0},
                            {spikeXY, spike.heightM - 0.5 * spike.heightAboveNeighboursM})});
    // The bit-flat lake from above.
    ASSERT_TRUE(terrain.value().lake().has_value());
    const io::TerrainLake& lake = *terrain.value().lake();
    const glm::dvec2 lakeXY = g.worldOfSample(lake.centreX, lake.centreY);
    poses.push_back(
        {"lake", lookingAt(kWidth, kHeight,
                           {lakeXY.x - 20.0 * g.sampleSpacing().x, lakeXY.y, lake.levelM + 300.0},
                           {lakeXY, lake.levelM})});
    // Grazing views 1 m above the ground, level, towards the horizon.
    poses.push_back(
        {"grazing 1 m east", groundPose(surface, kWidth, kHeight, 0.2, 0.5, 90.0, 0.0, 1.0)});
    poses.push_back({"grazing 1 m north-west",
                     groundPose(surface, kWidth, kHeight, 0.7, 0.8, -45.0, 0.0, 1.0)});
    // The whole terrain from far away.
    poses.push_back({"whole terrain", wholeTerrainPose(g, kWidth, kHeight)});
    std::mt19937_64 random(17);
    poses.push_back({"random full view", randomFullView(g, kWidth, kHeight, random)});

    sweep(pyramid, poses, "procedural", kWidth, kHeight, kErrorsPx);
    sweepOtherMethods(pyramid, poses, "procedural", kWidth, kHeight, kErrorsPx);
}

/// Smooth hills with hashed noise of ±3 m, 30 m apart: terrain for the scenes the
/// procedural DEM does not have.
float hills(std::int64_t x, std::int64_t y) {
    std::uint64_t h = static_cast<std::uint64_t>(x) * 0x9E3779B97F4A7C15ULL ^
                      static_cast<std::uint64_t>(y) * 0xBF58476D1CE4E5B9ULL;
    h ^= h >> 31U;
    h *= 0xD6E8FEB86659FD93ULL;
    h ^= h >> 32U;
    const double noise = static_cast<double>(h % 601) / 100.0 - 3.0;
    const auto fx = static_cast<double>(x), fy = static_cast<double>(y);
    return static_cast<float>(600.0 + 250.0 * std::sin(fx * 0.031) * std::cos(fy * 0.023) +
                              120.0 * std::sin(fx * 0.11 + fy * 0.07) + noise);
}

TEST_F(AccuracyStabilityTest, NoDataHoles) {
    // A DEM with no-data: round voids (one on the DEM's edge), a void whose fill spans a
    // valley, and a whole row without one valid sample, which the builder fills from the rows
    // beside it (the membrane, docs/pyramid-format.md, "No-data"; a fill along the row made
    // it a one-sample trench at 0 m, 300–1,000 m deep).
    constexpr std::int64_t kSize = 257;
    constexpr std::int64_t kEmptyRow = 150;
    const auto isVoid = [](std::int64_t x, std::int64_t y) {
        const auto inDisc = [&](double cx, double cy, double r) {
            return (static_cast<double>(x) - cx) * (static_cast<double>(x) - cx) +
                       (static_cast<double>(y) - cy) * (static_cast<double>(y) - cy) <=
                   r * r;
        };
        return y == kEmptyRow || inDisc(60, 70, 12) || inDisc(0, 200, 20) || inDisc(180, 90, 25);
    };
    FunctionDem dem(
        kSize, kSize, 30.0,
        [&](std::int64_t x, std::int64_t y) {
            return isVoid(x, y) ? std::numeric_limits<float>::quiet_NaN() : hills(x, y);
        },
        true);
    const TempFolder folder;
    const std::filesystem::path pyramid = buildScenePyramid(dem, folder, "nodata");
    auto surfaceOpened = runtime::FullResolutionSurface::open(pyramid);
    ASSERT_TRUE(surfaceOpened) << surfaceOpened.error().message;
    runtime::FullResolutionSurface& surface = surfaceOpened.value();
    auto reader = io::PyramidReader::open(pyramid);
    ASSERT_TRUE(reader) << reader.error().message;
    ASSERT_TRUE(reader.value().hasMask()) << "the scene must have no-data";
    EXPECT_GT(reader.value().manifest().noData.samples, kSize);
    // The row without data lies between the rows beside it: no trench.
    auto trench = surface.sample(100, kEmptyRow);
    auto north = surface.sample(100, kEmptyRow - 1), south = surface.sample(100, kEmptyRow + 1);
    ASSERT_TRUE(trench && north && south);
    EXPECT_NEAR(trench.value(), 0.5f * (north.value() + south.value()), 1.0f);

    const runtime::TerrainGeometry& g = surface.geometry();
    const glm::dvec2 voidXY = g.worldOfSample(180.0, 90.0);
    const glm::dvec2 trenchXY = g.worldOfSample(100.0, kEmptyRow);
    std::vector<Pose> poses;
    poses.push_back({"over a filled void",
                     lookingAt(kWidth, kHeight, {voidXY.x - 900.0, voidXY.y - 900.0, 1500.0},
                               {voidXY, 500.0})});
    poses.push_back({"along the empty row",
                     lookingAt(kWidth, kHeight, {trenchXY.x - 2000.0, trenchXY.y + 60.0, 900.0},
                               {trenchXY.x + 1000.0, trenchXY.y, 0.0})});
    poses.push_back({"grazing 1 m towards the trench",
                     groundPose(surface, kWidth, kHeight, 0.4, 0.45, 180.0, 0.0, 1.0)});
    poses.push_back({"whole terrain", wholeTerrainPose(g, kWidth, kHeight)});
    sweep(pyramid, poses, "no-data", kWidth, kHeight, kErrorsPx);
    sweepOtherMethods(pyramid, poses, "no-data", kWidth, kHeight, kErrorsPx);
}

/// Heights of a coarse grid read at the wrong spacing (issue 16: a 5 km polar grid built at
/// 1 m): 1 m apart on the ground, up to thousands of metres apart in height, everywhere.
float needles(std::int64_t x, std::int64_t y) {
    std::uint64_t h = static_cast<std::uint64_t>(x) * 0xD1B54A32D192ED03ULL ^
                      static_cast<std::uint64_t>(y) * 0x8CB92BA72F3D8DD7ULL;
    h ^= h >> 29U;
    h *= 0xBF58476D1CE4E5B9ULL;
    h ^= h >> 32U;
    const auto fx = static_cast<double>(x), fy = static_cast<double>(y);
    return static_cast<float>(1500.0 + 1200.0 * std::sin(fx * 0.05) * std::cos(fy * 0.04) +
                              static_cast<double>(h % 3001));
}

// The whole of a hilly DEM from beyond its south edge (wholeTerrainPose): no skirt hangs from
// the DEM's own edge, where no patch lies beyond to crack against (issue 46: it was a wall
// below the outline facing the camera, drawn where the reference shows the sky); inside,
// the skirts are hidden by the surface seen from above.
TEST_F(AccuracyStabilityTest, NoSkirtHangsFromTheDemsOwnEdge) {
    FunctionDem dem(257, 257, 30.0, hills, false);
    const TempFolder folder;
    const std::filesystem::path pyramid = buildScenePyramid(dem, folder, "hills");
    auto opened = runtime::TerrainSession::open(pyramid, roomySessionOptions(2.0));
    ASSERT_TRUE(opened) << opened.error().message;
    auto probe = runtime::AccuracyProbe::create(pyramid, {.widthPx = kWidth, .heightPx = kHeight});
    ASSERT_TRUE(probe) << probe.error().message;
    auto surface = runtime::FullResolutionSurface::open(pyramid);
    ASSERT_TRUE(surface) << surface.error().message;
    const runtime::Camera camera = wholeTerrainPose(surface.value().geometry(), kWidth, kHeight);
    const SettledMeasure m = measureSettled(*opened.value(), *probe.value(), camera, 2.0);
    const runtime::FrameAccuracy& a = m.accuracy;
    std::cout << "[          ] whole hills from beyond the edge: " << a.lodPixels
              << " terrain pixels drawn, the reference " << a.referencePixels << "; " << describe(a)
              << "\n";
    // Where the reference shows the sky the measure has nothing to compare: the pixels the
    // LOD draws beyond the reference's are what a wall would add (the silhouette, within ε,
    // takes or gives a pixel here and there).
    EXPECT_LE(a.lodPixels, a.referencePixels + a.referencePixels / 500) << describe(a);
    EXPECT_EQ(a.overdrawnPixels, 0u) << describe(a);
    EXPECT_EQ(a.crackPixels(), 0u) << describe(a);
}

TEST_F(AccuracyStabilityTest, NeedleForestOfExtremeRelief) {
    // Slopes of up to 4,000 between adjacent samples (89.99°): the LOD's bound holds as
    // on any terrain, but a drawn point the rasteriser puts a fraction of a pixel sideways
    // is pixels off vertically, which the measure's horizontal tolerance accounts for
    // (docs/accuracy.md, "Steep slopes"); and no crack opens between the needles.
    constexpr std::int64_t kSize = 257;
    FunctionDem dem(kSize, kSize, 1.0, needles, false);
    const TempFolder folder;
    // Blocks of 16 quads, not the default 8: with blocks of 8 the crack test counts one pixel
    // of "among the needles" for every method, the uniform grid (every patch at full
    // resolution, no T-junction) included. The full-resolution mesh has no gap, so that is
    // the crack test's diagonal-coverage edge case, not the LOD's (docs/accuracy.md,
    // "Stability suite"); it is not resolved yet.
    const std::filesystem::path pyramid = buildScenePyramid(dem, folder, "needles", 65, 16);
    auto surfaceOpened = runtime::FullResolutionSurface::open(pyramid);
    ASSERT_TRUE(surfaceOpened) << surfaceOpened.error().message;
    runtime::FullResolutionSurface& surface = surfaceOpened.value();
    const runtime::TerrainGeometry& g = surface.geometry();
    const glm::dvec2 centre = g.worldAtFraction(0.5, 0.5);
    std::vector<Pose> poses;
    poses.push_back({"whole forest", wholeTerrainPose(g, kWidth, kHeight)});
    poses.push_back(
        {"above the needles, looking down at 45°",
         lookingAt(kWidth, kHeight, {centre.x - 60.0, centre.y - 60.0, 7000.0}, {centre, 3000.0})});
    // 5 m above the highest sample around it, lower than most needles further on.
    const glm::dvec2 among{centre.x - 100.0, centre.y - 20.0};
    poses.push_back(
        {"among the needles, looking along them",
         lookingAt(kWidth, kHeight, {among, groundHeightNear(surface, among.x, among.y) + 5.0},
                   {centre.x + 100.0, centre.y + 20.0, 2000.0})});
    sweep(pyramid, poses, "needles", kWidth, kHeight, kErrorsPx);
    sweepOtherMethods(pyramid, poses, "needles", kWidth, kHeight, kErrorsPx);
}

TEST_F(AccuracyStabilityTest, TenThousandKilometresFromTheOrigin) {
    // The same procedural terrain placed at its usual origin and 10,000 km away (a DEM far
    // out on a planet-sized projected grid, as terrain-build --origin does): cameras at the
    // same place relative to the DEM must see the same picture — no float precision lost to
    // the far placement, no jitter at 1 m — and the far one is as accurate as the near one.
    const TempFolder folder;
    auto nearReader = io::openProceduralDem("procedural:size=257,seed=9");
    ASSERT_TRUE(nearReader) << nearReader.error().message;
    auto farReader =
        io::openProceduralDem("procedural:size=257,seed=9", [](io::DemInfo& info) -> Status {
            info.georeference.originX = 1.0e7;  // as terrain-build --origin 1e7,1e7
            info.georeference.originY = 1.0e7;
            return {};
        });
    ASSERT_TRUE(farReader) << farReader.error().message;
    const std::filesystem::path nearPyramid =
        buildScenePyramid(*nearReader.value(), folder, "near");
    const std::filesystem::path farPyramid = buildScenePyramid(*farReader.value(), folder, "far");

    auto nearSurface = runtime::FullResolutionSurface::open(nearPyramid);
    auto farSurface = runtime::FullResolutionSurface::open(farPyramid);
    ASSERT_TRUE(nearSurface && farSurface);
    const glm::dvec2 offset =
        farSurface.value().geometry().origin() - nearSurface.value().geometry().origin();
    EXPECT_GT(farSurface.value().geometry().origin().x, 9.9e6);
    EXPECT_GT(farSurface.value().geometry().origin().y, 9.9e6);

    // Poses made on the near terrain, moved by the offset for the far one.
    std::vector<Pose> nearPoses;
    nearPoses.push_back({"grazing 1 m", groundPose(nearSurface.value(), kWidth, kHeight, 0.3, 0.4,
                                                   30.0, 0.0, 1.0)});
    nearPoses.push_back({"grazing 1 m, 1 cm further", nearPoses.back().camera});
    nearPoses.back().camera.position.x += 0.01;
    nearPoses.push_back({"low oblique", groundPose(nearSurface.value(), kWidth, kHeight, 0.6, 0.7,
                                                   200.0, -20.0, 60.0)});
    std::vector<Pose> farPoses = nearPoses;
    for (Pose& p : farPoses) p.camera.position += glm::dvec3(offset, 0.0);

    // The pictures agree, frame by frame, to a few 8-bit levels at most (float rounding of
    // the positions relative to the camera's sample differs by at most an ulp).
    for (const double errorPx : kErrorsPx) {
        auto nearSession = runtime::TerrainSession::open(nearPyramid, roomySessionOptions(errorPx));
        auto farSession = runtime::TerrainSession::open(farPyramid, roomySessionOptions(errorPx));
        ASSERT_TRUE(nearSession && farSession);
        auto nearProbe =
            runtime::AccuracyProbe::create(nearPyramid, {.widthPx = kWidth, .heightPx = kHeight});
        auto farProbe =
            runtime::AccuracyProbe::create(farPyramid, {.widthPx = kWidth, .heightPx = kHeight});
        ASSERT_TRUE(nearProbe && farProbe);
        for (std::size_t i = 0; i < nearPoses.size(); ++i) {
            const SettledMeasure n = measureSettled(*nearSession.value(), *nearProbe.value(),
                                                    nearPoses[i].camera, errorPx);
            const SettledMeasure f =
                measureSettled(*farSession.value(), *farProbe.value(), farPoses[i].camera, errorPx);
            const std::string what = nearPoses[i].name + " at ε = " + std::to_string(errorPx);
            std::cout << "[          ] near / " << what << ": " << describe(n.accuracy) << "\n";
            std::cout << "[          ] far  / " << what << ": " << describe(f.accuracy) << "\n";
            expectStable("far / " + what, farPoses[i].camera, f);
            EXPECT_LE(n.accuracy.error.maxPx, errorPx + kRasterTolerancePx) << "near / " << what;
            EXPECT_LE(f.accuracy.error.maxPx, errorPx + kRasterTolerancePx) << "far / " << what;
            EXPECT_EQ(n.triangles, f.triangles) << what;
            EXPECT_EQ(n.patches, f.patches) << what;
            EXPECT_NEAR(f.accuracy.error.maxPx, n.accuracy.error.maxPx, 0.01) << what;
            // The probes' last LOD images: the far picture is the near one.
            EXPECT_NEAR(f.accuracy.image.psnrDb, n.accuracy.image.psnrDb, 0.5) << what;
            EXPECT_LT(std::abs(f.accuracy.image.rmse - n.accuracy.image.rmse), 0.1) << what;
        }
    }
}

TEST_F(AccuracyStabilityTest, TeleportsFasterThanStreaming) {
    // Teleports between grazing and overview poses every 1–3 frames while tiles arrive
    // slowly (2 ms added latency, two uploads a frame, a small pool) and some fail: every
    // frame, settled or not, is compared with the reference. Frames waiting for tiles draw
    // coarser ancestors, so their error is not bounded by ε; but they never crack, never
    // leave a hole inside the reference's footprint, and never produce NaN. Once streaming
    // catches up the error bound holds again.
    const TempFolder folder;
    auto dem = io::openProceduralDem("procedural:size=513,seed=4");
    ASSERT_TRUE(dem) << dem.error().message;
    const std::filesystem::path pyramid = buildScenePyramid(*dem.value(), folder, "teleports");
    runtime::TerrainSessionOptions options = roomySessionOptions(2.0);
    options.streaming.gpuLayers = 96;
    options.streaming.cpuCacheBytes = 512 * 1024;
    options.streaming.uploadBytesPerFrame = 40 * 1024;
    options.streaming.io.faults = {.errorRate = 0.05, .addedLatencyMs = 2.0, .seed = 3};
    auto opened = runtime::TerrainSession::open(pyramid, options);
    ASSERT_TRUE(opened) << opened.error().message;
    runtime::TerrainSession& session = *opened.value();
    auto probe = runtime::AccuracyProbe::create(pyramid, {.widthPx = kWidth, .heightPx = kHeight});
    ASSERT_TRUE(probe) << probe.error().message;
    runtime::FullResolutionSurface& surface = probe.value()->surface();
    const runtime::TerrainGeometry& g = surface.geometry();

    std::mt19937_64 random(23);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const auto randomPose = [&]() {
        switch (static_cast<int>(u(random) * 3.0)) {
            case 0:
                return groundPose(surface, kWidth, kHeight, 0.1 + 0.8 * u(random),
                                  0.1 + 0.8 * u(random), 360.0 * u(random), -5.0 * u(random), 1.0);
            case 1:
                return randomFullView(g, kWidth, kHeight, random);
            default:
                return wholeTerrainPose(g, kWidth, kHeight);
        }
    };
    runtime::Camera camera = randomPose();
    waitForTheRoot(session, camera);
    ASSERT_FALSE(session.draws().empty()) << "the root never arrived";

    runtime::TerrainStyle style;
    style.fogDensityPerM = 0.0f;
    int frames = 0, waitingFrames = 0;
    std::uint64_t cracks = 0;
    double worstWaitingPx = 0.0;
    std::uniform_int_distribution<int> hold(1, 3);
    while (frames < 36) {
        camera = randomPose();
        for (int i = hold(random); i > 0 && frames < 36; --i, ++frames) {
            const runtime::LodUpdateStats lod = session.beginFrame(camera);
            auto measured = probe.value()->measure(session, camera, style);
            runtime::FrameTelemetry t;
            session.endFrame(t);
            ASSERT_TRUE(measured) << measured.error().message;
            const runtime::FrameAccuracy& a = measured.value();
            waitingFrames += lod.waitingSplits > 0 ? 1 : 0;
            cracks += a.crackPixels();
            EXPECT_EQ(a.crackPixels(), 0u)
                << "frame " << frames << ", " << describe(camera) << ": " << describe(a);
            EXPECT_TRUE(a.finite()) << "frame " << frames << ", " << describe(camera);
            if (lod.waitingSplits > 0) worstWaitingPx = std::max(worstWaitingPx, a.error.maxPx);
        }
    }
    std::cout << "[          ] " << frames << " frames, " << waitingFrames
              << " waiting for tiles (largest error then " << worstWaitingPx << " px), "
              << session.streamer().faults().size() << " failed tiles, " << cracks
              << " crack pixels\n";
    EXPECT_GT(waitingFrames, frames / 3) << "streaming must lag the teleports";
    EXPECT_GT(worstWaitingPx, 4.0) << "lagging frames should show coarse ancestors";
    // Settled again.
    const SettledMeasure m = measureSettled(session, *probe.value(), camera, 2.0);
    std::cout << "[          ] settled: " << describe(m.accuracy) << "\n";
    expectStable("settled after teleports", camera, m);
    // A failed tile keeps its parent drawn for good, so the bound holds only where nothing
    // failed.
    const SettledMeasure c =
        measureSettled(session, *probe.value(), camera, 2.0, g.layout().blockQuads());
    expectStable("settled after teleports (coarse LOD only)", camera, c);
    if (session.streamer().faults().empty()) {
        EXPECT_LE(m.accuracy.error.maxPx, 2.0 + kRasterTolerancePx) << describe(m.accuracy);
        EXPECT_LE(c.accuracy.error.maxPx, 2.0 + kRasterTolerancePx) << describe(c.accuracy);
    }
    EXPECT_TRUE(session.streamer().drain(std::chrono::seconds(10)));
}

}  // namespace
}  // namespace terrain::test
