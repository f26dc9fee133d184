// The reference renderer is right (DESIGN.md, "Measurement is part of the product"): every
// pixel it draws lies on the full-resolution mesh that FullResolutionSurface evaluates on
// the CPU (depth unprojected in double, and its world-height target), so the ground truth
// and the error measure agree on what the truth is. And the measures have a floor of
// (almost) zero: an LOD drawn at full resolution — every patch at the finest level, every
// block edge unsimplified — measures within the rasterisation tolerance of the reference,
// looks the same (shading shared through terrain_shading.glsl) and has no cracks; that
// floor is where kRasterTolerancePx comes from (docs/accuracy.md).
#include "AccuracyScenes.h"
#include "GlTestFixture.h"
#include "TempFolder.h"
#include "TerrainViewChecks.h"
#include "terrain/source/ProceduralDems.h"
#include "terrain/source/DemReader.h"
#include "terrain/runtime/AccuracyProbe.h"
#include "terrain/runtime/PlaneTruth.h"
#include "terrain/runtime/ScreenSpaceError.h"

#include <glm/matrix.hpp>

#include <cmath>
#include <iostream>
#include <random>

namespace terrain::test {
namespace {

constexpr int kWidth = 256;
constexpr int kHeight = 192;

class ReferenceRendererTest : public GlTest {
protected:
    static void SetUpTestSuite() {
        GlTest::SetUpTestSuite();
        folder() = std::make_unique<TempFolder>();
        auto reader = io::openProceduralDem("procedural:size=257,seed=3");
        ASSERT_TRUE(reader) << reader.error().message;
        pyramid() = buildScenePyramid(*reader.value(), *folder(), "procedural");
    }
    static void TearDownTestSuite() {
        folder().reset();
        GlTest::TearDownTestSuite();
    }
    static std::unique_ptr<TempFolder>& folder() {
        static std::unique_ptr<TempFolder> f;
        return f;
    }
    static std::filesystem::path& pyramid() {
        static std::filesystem::path p;
        return p;
    }

    /// Poses over the scene: steep full views and a grazing one at 2 m.
    static std::vector<runtime::Camera> poses(runtime::FullResolutionSurface& surface) {
        std::mt19937_64 random(5);
        std::vector<runtime::Camera> out;
        for (int i = 0; i < 3; ++i)
            out.push_back(randomFullView(surface.geometry(), kWidth, kHeight, random));
        out.push_back(groundPose(surface, kWidth, kHeight, 0.3, 0.6, 70.0, -2.0, 2.0));
        out.push_back(wholeTerrainPose(surface.geometry(), kWidth, kHeight));
        return out;
    }
};

TEST_F(ReferenceRendererTest, EveryPixelLiesOnTheFullResolutionMesh) {
    auto probe =
        runtime::AccuracyProbe::create(pyramid(), {.widthPx = kWidth, .heightPx = kHeight});
    ASSERT_TRUE(probe) << probe.error().message;
    runtime::FullResolutionSurface& surface = probe.value()->surface();
    for (const runtime::Camera& camera : poses(surface)) {
        auto reference = probe.value()->renderReference(camera, {});
        ASSERT_TRUE(reference) << reference.error().message;
        const runtime::FrameImages& img = reference.value().images;
        ASSERT_EQ(img.heightM.size(), img.pixels());
        EXPECT_GT(reference.value().draw.tiles, 0u);
        // The reference's depth measured as if it were an LOD frame: against its own
        // diagonal (the fixed-diagonal figure) it must be exact up to rounding.
        runtime::PlaneTruth truth(surface);
        auto self = runtime::measureScreenSpaceError(camera, img.depth, {}, {}, truth, 1.0);
        ASSERT_TRUE(self) << self.error().message;
        const runtime::ScreenSpaceErrorStats& e = self.value();
        std::cout << "[          ] " << describe(camera) << ": " << e.pixels
                  << " pixels, largest projected distance to the CPU mesh " << e.maxFixedDiagonalPx
                  << " px (nearer diagonal " << e.maxPx << ")\n";
        EXPECT_GT(e.pixels, img.pixels() / 5) << describe(camera);
        EXPECT_LT(e.maxFixedDiagonalPx, kRasterTolerancePx) << describe(camera);
        EXPECT_EQ(e.outsidePixels, 0u) << describe(camera);
        EXPECT_EQ(e.nonFinitePixels, 0u) << describe(camera);
        // The world-height target holds the mesh's height where the depth says.
        const glm::dmat4 inverse = glm::inverse(camera.relativeViewProjection());
        double worstRelative = 0.0;
        for (int y = 0; y < kHeight; ++y) {
            for (int x = 0; x < kWidth; ++x) {
                const std::size_t i = static_cast<std::size_t>(y * kWidth + x);
                if (!img.drawn(i)) {
                    EXPECT_TRUE(std::isnan(img.heightM[i]));
                    continue;
                }
                const glm::dvec3 rel =
                    runtime::unprojectPixel(inverse, kWidth, kHeight, x, y, img.depth[i]);
                const double z = camera.position.z + rel.z;
                worstRelative = std::max(
                    worstRelative, std::abs(img.heightM[i] - z) / std::max(1.0, glm::length(rel)));
            }
        }
        EXPECT_LT(worstRelative, 1e-4) << describe(camera);
    }
}

TEST_F(ReferenceRendererTest, FullResolutionLodMeasuresWithinTheTolerance) {
    // ε far below a pixel: the coarse LOD splits every visible patch down to the finest
    // level (Err(P) = 0 only there) and the fine LOD keeps every edge at d = 0 except on
    // exactly flat blocks, whose simplification changes nothing.
    constexpr double kTinyErrorPx = 1e-3;
    auto opened = runtime::TerrainSession::open(pyramid(), roomySessionOptions(kTinyErrorPx));
    ASSERT_TRUE(opened) << opened.error().message;
    auto probe =
        runtime::AccuracyProbe::create(pyramid(), {.widthPx = kWidth, .heightPx = kHeight});
    ASSERT_TRUE(probe) << probe.error().message;
    const int finest = opened.value()->surface().layout().finestLevel();
    for (const runtime::Camera& camera : poses(probe.value()->surface())) {
        const SettledMeasure m =
            measureSettled(*opened.value(), *probe.value(), camera, kTinyErrorPx);
        for (const runtime::PatchDraw& d : opened.value()->draws()) {
            EXPECT_EQ(d.id.level, finest);
        }
        const runtime::FrameAccuracy& a = m.accuracy;
        std::cout << "[          ] " << describe(camera) << ": " << describe(a) << "\n";
        EXPECT_TRUE(a.finite()) << describe(camera);
        EXPECT_GT(a.error.pixels, 0u);
        EXPECT_LE(a.error.maxPx, kRasterTolerancePx) << describe(camera) << ": " << describe(a);
        EXPECT_EQ(a.crackPixels(), 0u) << describe(camera);
        EXPECT_EQ(a.error.outsidePixels, 0u) << describe(camera);
    }
}

// A lossy pyramid (terrain-build --max-error-m) is measured against its lossless build: the
// probe's truth is then the source's own samples, not the lossy finest level, which lies up
// to δ off them. A reference of another layout is refused.
TEST_F(ReferenceRendererTest, ALossyPyramidIsMeasuredAgainstItsLosslessBuild) {
    auto reader = io::openProceduralDem("procedural:size=257,seed=3");
    ASSERT_TRUE(reader) << reader.error().message;
    const std::filesystem::path lossy = buildScenePyramid(
        *reader.value(), *folder(), "lossy", 65, io::PyramidLayout::kDefaultBlockQuads, 2.0);
    auto measured =
        runtime::AccuracyProbe::create(lossy, {.widthPx = kWidth, .heightPx = kHeight}, pyramid());
    ASSERT_TRUE(measured) << measured.error().message;
    auto own = runtime::AccuracyProbe::create(lossy, {.widthPx = kWidth, .heightPx = kHeight});
    ASSERT_TRUE(own) << own.error().message;
    auto exact =
        runtime::AccuracyProbe::create(pyramid(), {.widthPx = kWidth, .heightPx = kHeight});
    ASSERT_TRUE(exact) << exact.error().message;
    const runtime::TerrainGeometry& geometry = exact.value()->surface().geometry();
    double largestOwn = 0.0;
    for (const double f : {0.13, 0.5, 0.77}) {
        const glm::dvec2 at = geometry.worldOfSample(f * 256.0, (1.0 - f) * 256.0);
        auto truth = exact.value()->surface().heightAt(at.x, at.y);
        auto reference = measured.value()->surface().heightAt(at.x, at.y);
        auto quantized = own.value()->surface().heightAt(at.x, at.y);
        ASSERT_TRUE(truth && reference && quantized);
        EXPECT_EQ(reference.value().referenceM, truth.value().referenceM);
        largestOwn =
            std::max(largestOwn, std::abs(quantized.value().referenceM - truth.value().referenceM));
    }
    EXPECT_GT(largestOwn, 0.0);  // the lossy finest level is not the truth
    EXPECT_LE(largestOwn, 2.0 + 1e-3);

    auto other = io::openProceduralDem("procedural:size=129,seed=3");
    ASSERT_TRUE(other) << other.error().message;
    const std::filesystem::path small = buildScenePyramid(*other.value(), *folder(), "small");
    auto refused =
        runtime::AccuracyProbe::create(lossy, {.widthPx = kWidth, .heightPx = kHeight}, small);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().message.find("layout and georeference"), std::string::npos)
        << refused.error().message;
}

}  // namespace
}  // namespace terrain::test
