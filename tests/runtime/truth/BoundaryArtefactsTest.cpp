// Boundary artefacts (BoundaryArtefacts.h): on made-up images, a pinhole between two patches
// and a wrongly shaded edge pixel count, and a silhouette a pixel off, an occluding crest a
// pixel off, a real ridge, a step,
// detail drawn a pixel off (within the allowed shift), a silhouette's layers and a faint
// difference do not;
// on real draws of the streaming test pyramid (random full views, mixed levels, the patch-id
// view for the boundaries, the reference renderer for the truth), a draw without skirts (the
// deliberately broken draw: its T-junction and rounding gaps show the clear colour) has
// some, the draw as it is has none.
#include "GlTestFixture.h"
#include "StreamingTestPyramid.h"
#include "TerrainViewChecks.h"
#include "terrain/runtime/AccuracyProbe.h"
#include "terrain/runtime/BoundaryArtefacts.h"
#include "terrain/runtime/BoundaryShading.h"
#include "terrain/runtime/TerrainSession.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <random>
#include <vector>

namespace terrain::test {
namespace {

constexpr int kW = 8;
constexpr int kH = 5;
constexpr float kNearDepth = 1e-3f;  // reversed Z: near / distance

struct Images {
    runtime::FrameImages lod = blank();
    runtime::FrameImages reference = blank();
    std::vector<std::uint32_t> ids = std::vector<std::uint32_t>(kW * kH, 0);

    static runtime::FrameImages blank() {
        runtime::FrameImages images;
        images.width = kW;
        images.height = kH;
        images.rgba.assign(4 * kW * kH, 255);
        images.depth.assign(kW * kH, kNearDepth);
        return images;
    }
    static std::size_t at(int x, int y) { return static_cast<std::size_t>(y * kW + x); }
    static void put(runtime::FrameImages& image, int x, int y, std::array<int, 3> rgb) {
        for (std::size_t c = 0; c < 3; ++c)
            image.rgba[4 * at(x, y) + c] = static_cast<std::uint8_t>(rgb[c]);
    }
    std::size_t findAll(int shiftPx = 0) const {
        return runtime::findBoundaryArtefacts(lod, ids, reference, shiftPx).pixels.size();
    }
};

/// Patch 1 on the left half, patch 2 on the right, one surface, a gentle ramp of grey in
/// both images.
Images twoPatches() {
    Images images;
    for (int y = 0; y < kH; ++y) {
        for (int x = 0; x < kW; ++x) {
            const int grey = 120 + 4 * x;
            Images::put(images.lod, x, y, {grey, grey, grey});
            Images::put(images.reference, x, y, {grey, grey, grey});
            images.ids[Images::at(x, y)] = x < kW / 2 ? 1u : 2u;
        }
    }
    return images;
}

TEST(BoundaryArtefacts, PatchIdsDecodeTheViewsBytes) {
    const std::vector<std::uint8_t> rgba{0, 0, 0, 255, 1, 0, 0, 255, 0x34, 0x12, 0x05, 255};
    EXPECT_EQ(runtime::patchIdsOf(rgba), (std::vector<std::uint32_t>{0u, 1u, 0x051234u}));
}

TEST(BoundaryArtefacts, PinholesAndEdgeShadingCountAndNothingElseDoes) {
    const Images clean = twoPatches();
    EXPECT_EQ(clean.findAll(), 0u);
    EXPECT_EQ(runtime::findBoundaryArtefacts(clean.lod, clean.ids, clean.reference).boundaryPixels,
              2u * kH);  // columns 3 and 4

    // A pinhole: the sky (no patch, nothing drawn) between the two patches.
    Images hole = twoPatches();
    Images::put(hole.lod, 4, 2, {5, 8, 20});
    hole.ids[Images::at(4, 2)] = 0;
    hole.lod.depth[Images::at(4, 2)] = 0.0f;
    EXPECT_EQ(hole.findAll(), 1u);
    // The far side of the globe seen through it: another patch, dark and far.
    Images farSide = twoPatches();
    Images::put(farSide.lod, 3, 1, {29, 33, 22});
    farSide.ids[Images::at(3, 1)] = 7;
    farSide.lod.depth[Images::at(3, 1)] = kNearDepth / 1000.0f;
    EXPECT_EQ(farSide.findAll(), 1u);
    // The right patch's edge pixel, on the reference's surface, shaded dark.
    Images edge = twoPatches();
    Images::put(edge.lod, 4, 3, {10, 10, 10});
    EXPECT_EQ(edge.findAll(), 1u);

    // Dark inside a patch, away from any boundary: not this detector's.
    Images inside = twoPatches();
    Images::put(inside.lod, 1, 2, {0, 0, 0});
    EXPECT_EQ(inside.findAll(), 0u);
    // A silhouette drawn a pixel off the reference's: the farther surface of one side.
    Images silhouette = twoPatches();
    Images::put(silhouette.lod, 4, 3, {10, 10, 10});
    silhouette.lod.depth[Images::at(4, 3)] = kNearDepth / 2.0f;
    EXPECT_EQ(silhouette.findAll(), 0u);
    // An occluding edge the LOD draws a pixel off: the edge pixel lies on the reference's
    // surface (depths within kSameSurface) but a nearer ridge's crest, shaded apart, covers
    // it in the LOD and the row above in the reference; the ground rises in depth as a
    // plane's does (reversed Z affine in screen space), the crest stands 1 % nearer.
    Images crest = twoPatches();
    for (Images* images : {&crest, &edge}) {
        for (int y = 0; y < kH; ++y) {
            for (int x = 0; x < kW; ++x) {
                const float depth = kNearDepth * (1.0f + 0.002f * float(y));
                images->lod.depth[Images::at(x, y)] = depth;
                images->reference.depth[Images::at(x, y)] = depth;
            }
        }
    }
    for (int x = 0; x < kW; ++x) {
        crest.lod.depth[Images::at(x, 3)] *= 1.01f;
        crest.lod.depth[Images::at(x, 4)] *= 1.01f;
        crest.reference.depth[Images::at(x, 4)] *= 1.01f;
    }
    Images::put(crest.lod, 4, 3, {10, 10, 10});
    EXPECT_EQ(crest.findAll(), 0u);
    // The same dark edge pixel on the smooth ramp, no silhouette near: counted.
    EXPECT_EQ(edge.findAll(), 1u);
    // A silhouette's layers: between a near patch and a far one, a pixel of a third patch
    // at a depth between theirs (a ridge seen between the two), not a gap.
    Images layers = twoPatches();
    for (int y = 0; y < kH; ++y)
        for (int x = kW / 2; x < kW; ++x) layers.lod.depth[Images::at(x, y)] = kNearDepth / 4.0f;
    Images::put(layers.lod, 4, 2, {10, 10, 10});
    layers.ids[Images::at(4, 2)] = 3;
    layers.lod.depth[Images::at(4, 2)] = kNearDepth / 2.0f;
    EXPECT_EQ(layers.findAll(), 0u);
    // On the boundary and standing out, but the reference has it too (a real ridge).
    Images ridge = twoPatches();
    Images::put(ridge.lod, 4, 3, {250, 250, 250});
    Images::put(ridge.reference, 4, 3, {250, 250, 250});
    EXPECT_EQ(ridge.findAll(), 0u);
    // A step at the boundary: the pixel differs from the other side only.
    Images step = twoPatches();
    for (int y = 0; y < kH; ++y)
        for (int x = kW / 2; x < kW; ++x) Images::put(step.lod, x, y, {40, 40, 40});
    EXPECT_EQ(step.findAll(), 0u);
    // Detailed ground drawn a pixel off (within ε = 1 px): the edge pixel shows a dark
    // feature the reference has one pixel lower. Counted when no shift is allowed, not when
    // the LOD's ε allows one.
    Images shifted = twoPatches();
    Images::put(shifted.lod, 4, 2, {10, 10, 10});
    Images::put(shifted.reference, 4, 3, {10, 10, 10});
    EXPECT_EQ(shifted.findAll(0), 1u);
    EXPECT_EQ(shifted.findAll(1), 0u);
    // The same shift allowance does not excuse a dark pixel the reference shows nowhere near,
    // nor a pinhole.
    EXPECT_EQ(edge.findAll(1), 1u);
    EXPECT_EQ(hole.findAll(1), 1u);
    // Just under the threshold: not a visible artefact.
    Images faint = twoPatches();
    const int grey = 120 + 4 * 4 - runtime::BoundaryArtefacts::kDefaultThresholdLevels;
    Images::put(faint.lod, 4, 2, {grey + 4, grey + 4, grey + 4});
    EXPECT_EQ(faint.findAll(), 0u);
}

// The shading-step measure (BoundaryShading.h) on the same made-up images: a patch shaded
// apart from its neighbour steps at the boundary; a step the reference has, a silhouette and
// detail inside a patch do not count as a seam.
TEST(BoundaryShading, AStepTheReferenceLacksIsASeamAndNothingElseIs) {
    const auto measure = [](const Images& images) {
        return runtime::measureBoundaryShading(images.lod, images.ids, images.reference);
    };
    const Images clean = twoPatches();
    EXPECT_EQ(measure(clean).boundaryPairs, std::uint64_t{kH});
    EXPECT_EQ(measure(clean).seamLevels(), 0.0);

    // The right patch 40 levels brighter than the reference: every boundary pair steps by
    // 40 more than the reference, no interior pair does.
    Images brighter = twoPatches();
    for (int y = 0; y < kH; ++y)
        for (int x = kW / 2; x < kW; ++x)
            Images::put(brighter.lod, x, y, {160 + 4 * x, 160 + 4 * x, 160 + 4 * x});
    EXPECT_NEAR(measure(brighter).boundaryExcessLevels, 40.0, 1e-9);
    EXPECT_NEAR(measure(brighter).interiorExcessLevels, 0.0, 1e-9);
    EXPECT_NEAR(measure(brighter).seamLevels(), 40.0, 1e-9);
    // The reference has the same step (a real change of slope along the boundary): no seam.
    Images ridge = brighter;
    ridge.reference = ridge.lod;
    EXPECT_NEAR(measure(ridge).seamLevels(), 0.0, 1e-9);
    // The right side is another, farther surface (a silhouette): not compared.
    Images silhouette = brighter;
    for (int y = 0; y < kH; ++y)
        for (int x = kW / 2; x < kW; ++x)
            silhouette.lod.depth[Images::at(x, y)] = kNearDepth / 4.0f;
    EXPECT_EQ(measure(silhouette).boundaryPairs, 0u);
    // Noise inside the patches as much as across their boundary: no seam.
    Images noisy = twoPatches();
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x)
            if ((x + y) % 2 == 0) Images::put(noisy.lod, x, y, {200, 200, 200});
    const runtime::BoundaryShading noise = measure(noisy);
    EXPECT_GT(noise.interiorExcessLevels, 10.0);
    EXPECT_NEAR(noise.seamLevels(), 0.0, 12.0);
}

class BoundaryArtefactsDrawTest : public GlTest {};

TEST_F(BoundaryArtefactsDrawTest, ADrawWithoutSkirtsHasThemAndTheDrawHasNone) {
    constexpr int kWidth = 320;
    constexpr int kHeight = 240;
    constexpr int kPoses = 6;
    runtime::TerrainSessionOptions options;
    options.streaming.gpuLayers = 512;  // holds every patch of the pyramid
    options.streaming.cpuCacheBytes = std::size_t{256} << 20;
    options.streaming.uploadBytesPerFrame = std::size_t{64} << 20;
    auto opened = runtime::TerrainSession::open(streamingTestPyramid(), options);
    ASSERT_TRUE(opened) << opened.error().message;
    runtime::TerrainSession& session = *opened.value();
    auto probeOpened = runtime::AccuracyProbe::create(streamingTestPyramid(),
                                                      {.widthPx = kWidth, .heightPx = kHeight});
    ASSERT_TRUE(probeOpened) << probeOpened.error().message;
    runtime::AccuracyProbe& probe = *probeOpened.value();
    const runtime::TerrainGeometry& g = probe.surface().geometry();

    std::mt19937_64 random(11);
    std::uint64_t withSkirts = 0, withoutSkirts = 0, boundaryPixels = 0, darkenedEdges = 0;
    std::uint64_t cracksWithSkirts = 0, cracksWithoutSkirts = 0;
    double shadedSeam = 0.0, brokenSeam = 0.0;
    for (int pose = 0; pose < kPoses; ++pose) {
        const runtime::Camera camera = randomFullView(g, kWidth, kHeight, random);
        // ε from 1 to 8 px: views that mix patch levels.
        const double errorPx =
            std::pow(8.0, std::uniform_real_distribution<double>(0.0, 1.0)(random));
        session.setErrorPx(errorPx);
        ASSERT_TRUE(session.settle(camera, std::chrono::seconds(60)));
        session.beginFrame(camera);
        runtime::TerrainStyle style;
        style.fogDensityPerM = 0.0f;
        auto reference = probe.renderReference(camera, runtime::referenceStyleOf(style));
        ASSERT_TRUE(reference) << reference.error().message;
        for (const bool skirts : {true, false}) {
            style.skirts = skirts;
            style.debugView = runtime::TerrainDebugView::Shaded;
            const runtime::LodCapture shaded = probe.captureLod(session, camera, style);
            style.debugView = runtime::TerrainDebugView::PatchId;
            const runtime::LodCapture patches = probe.captureLod(session, camera, style);
            const runtime::BoundaryArtefacts found = runtime::findBoundaryArtefacts(
                shaded.images, runtime::patchIdsOf(patches.images.rgba), reference.value().images);
            (skirts ? withSkirts : withoutSkirts) += found.pixels.size();
            // The probe's crack count (the truth covering the ray even lowered by ε) sees
            // the same gaps.
            auto accuracy = probe.compare(camera, shaded, reference.value(), errorPx);
            ASSERT_TRUE(accuracy) << accuracy.error().message;
            (skirts ? cracksWithSkirts : cracksWithoutSkirts) += accuracy.value().crackPixels();
            if (skirts) {
                const std::vector<std::uint32_t> ids = runtime::patchIdsOf(patches.images.rgba);
                shadedSeam +=
                    runtime::measureBoundaryShading(shaded.images, ids, reference.value().images)
                        .seamLevels();
                // The deliberately broken shading for the seam measure: the same frame with
                // the edge pixels of every other patch (odd draw index) 40 levels darker, a
                // patch edge shaded apart from its neighbour.
                runtime::FrameImages broken = shaded.images;
                for (std::size_t i = 0; i < ids.size(); ++i) {
                    if (ids[i] % 2 == 0 || !runtime::onPatchBoundary(ids, broken.width, i))
                        continue;
                    for (std::size_t c = 0; c < 3; ++c)
                        broken.rgba[4 * i + c] = static_cast<std::uint8_t>(
                            std::max(0, int{broken.rgba[4 * i + c]} - 40));
                }
                brokenSeam +=
                    runtime::measureBoundaryShading(broken, ids, reference.value().images)
                        .seamLevels();
                // The artefact detector sees those edge pixels too, away from silhouettes.
                darkenedEdges +=
                    runtime::findBoundaryArtefacts(broken, ids, reference.value().images)
                        .pixels.size();
                boundaryPixels += found.boundaryPixels;
                EXPECT_TRUE(found.pixels.empty())
                    << "pose " << pose << ": " << found.pixels.size()
                    << " boundary artefacts, the first at pixel " << found.pixels.front();
            }
        }
        runtime::FrameTelemetry ignored;
        session.endFrame(ignored);
    }
    std::cout << "[          ] " << kPoses << " poses, " << boundaryPixels
              << " boundary pixels: boundary artefacts " << withSkirts << " drawn as it is, "
              << withoutSkirts << " without skirts, " << darkenedEdges
              << " with patch edges shaded apart; crack pixels " << cracksWithSkirts << " and "
              << cracksWithoutSkirts << "; shading seam " << shadedSeam / kPoses
              << " levels a pose, " << brokenSeam / kPoses << " with patch edges shaded apart\n";
    EXPECT_GT(boundaryPixels, 0u) << "no patch boundary in view: the test shows nothing";
    EXPECT_EQ(withSkirts, 0u);
    // The control: the broken draw does show them, so the detector can fail.
    EXPECT_GT(withoutSkirts, 0u);
    EXPECT_GT(darkenedEdges, boundaryPixels / 10);
    EXPECT_EQ(cracksWithSkirts, 0u);
    EXPECT_GT(cracksWithoutSkirts, 0u);
    // The seam measure sees patch edges shaded apart (about half the boundary pairs step by
    // 40 levels); the draw as it is stays under the report's 1 level.
    EXPECT_GT(brokenSeam / kPoses, 10.0);
    EXPECT_LT(shadedSeam / kPoses, 1.0);
}

}  // namespace
}  // namespace terrain::test
