// ImageryReference (issue 47's measure): a pyramid with two imagery layers built by the
// imagery builder from one fake image, the second shifted by one image pixel (one texel of
// its finest level). The streamed, draped draw of a settled view must agree with the
// reference computed on the CPU from the tiles on disk, and the reference must see a
// one-texel shift (the same frame compared with the shifted layer's reference).
#include "AccuracyScenes.h"
#include "FakeImageryImage.h"
#include "GlTestFixture.h"
#include "TempFolder.h"
#include "terrain/runtime/AccuracyProbe.h"
#include "terrain/runtime/ImageryReference.h"
#include "terrain/runtime/ImageryTexelsPerPixel.h"
#include "terrain/runtime/PlaneSurface.h"
#include "terrain/runtime/TerrainSession.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>

namespace terrain::test {
namespace {

constexpr int kWidth = 320;
constexpr int kHeight = 240;
/// Image pixels per DEM sample: the imagery is 4 × finer than the DEM, as imagery often is.
constexpr double kPixelSamples = 0.25;

/// Slow waves in red and green, a fast one (a few pixels long, across both axes) in blue.
std::array<std::uint8_t, 4> pattern(std::int64_t x, std::int64_t y) {
    const double fx = static_cast<double>(x), fy = static_cast<double>(y);
    const auto level = [](double v) {
        return static_cast<std::uint8_t>(std::lround(127.5 + 100.0 * v));
    };
    return {level(std::sin(fx / 37.0)), level(std::cos(fy / 23.0)),
            level(std::sin((fx + 2.0 * fy) / 2.9)), 255};
}

class ImageryReferenceTest : public GlTest {
protected:
    void SetUp() override {
        GlTest::SetUp();
        // Rolling hills, 257² samples 30 m apart in patches of 65: levels 0 … 2.
        FunctionDem dem(
            257, 257, 30.0,
            [](std::int64_t x, std::int64_t y) {
                const double fx = static_cast<double>(x), fy = static_cast<double>(y);
                return static_cast<float>(300.0 + 60.0 * std::sin(fx / 23.0) * std::cos(fy / 31.0));
            },
            false);
        m_pyramid = buildScenePyramid(dem, m_folder, "hills");
        auto manifest = io::readManifest(m_pyramid);
        ASSERT_TRUE(manifest) << manifest.error().message;
        // "exact" lies on the samples; "shifted" is the same picture one pixel east.
        const auto pixels = static_cast<std::int64_t>(std::ceil(257.0 / kPixelSamples)) + 2;
        for (const auto& [name, x0] :
             {std::pair{"exact", 0.0}, std::pair{"shifted", kPixelSamples}}) {
            io::ImageryBuildOptions options;
            options.name = name;
            options.input = std::string(name) + ".tif";
            options.encoding.lossless = true;
            options.threads = 1;
            auto built = io::buildImageryLayer(
                m_pyramid, manifest.value(),
                fakeImageryOpener(pixels, pixels, x0, 0.0, kPixelSamples, pattern), options);
            ASSERT_TRUE(built) << built.error().message;
            manifest.value().imagery.push_back(built.value().layer);
        }
        ASSERT_TRUE(io::writeManifest(m_pyramid, manifest.value()));
    }

    struct Compared {
        runtime::ImageryFrameComparison exact;    ///< the drawn layer's reference
        runtime::ImageryFrameComparison shifted;  ///< the other layer's
        runtime::ImageryTexelsPerPixel gpu;       ///< the texels per pixel the draw read back
    };

    /// The settled view of `camera` draped with the "exact" layer alone, unlit, compared with
    /// both layers' references.
    Compared drapeAndCompare(
        const std::function<runtime::Camera(const runtime::TerrainGeometry&)>& pose) {
        runtime::TerrainSessionOptions options = roomySessionOptions(1.0);
        options.renderer.imageryTexelsPerPixel = true;
        auto opened = runtime::TerrainSession::open(m_pyramid, options);
        EXPECT_TRUE(opened) << opened.error().message;
        if (!opened) return {};
        runtime::TerrainSession& session = *opened.value();
        const runtime::Camera camera = pose(runtime::planeGeometry(session.surface()));
        auto probe =
            runtime::AccuracyProbe::create(m_pyramid, {.widthPx = kWidth, .heightPx = kHeight});
        EXPECT_TRUE(probe) << probe.error().message;
        auto reference = runtime::ImageryReference::open(m_pyramid, session.manifest());
        EXPECT_TRUE(reference) << reference.error().message;
        if (!probe || !reference) return {};
        EXPECT_EQ(reference.value()->layerCount(), 2);

        runtime::TerrainStyle drawn;
        drawn.imageryLighting = false;
        drawn.imageryOpacity = {1.0f, 0.0f, 1.0f, 1.0f};
        EXPECT_TRUE(session.settle(camera, std::chrono::seconds(60)));
        session.beginFrame(camera);
        runtime::TerrainDrawStats stats;
        std::vector<float> texelsPerPixel;
        const runtime::FrameImages frame =
            probe.value()->captureImage(session, camera, drawn, &stats, &texelsPerPixel);
        runtime::FrameTelemetry telemetry;
        session.endFrame(telemetry);
        EXPECT_EQ(stats.imageryLayers, 2);

        Compared out;
        out.gpu = runtime::summariseTexelsPerPixel(texelsPerPixel);
        auto exact = reference.value()->compare(camera, frame, drawn);
        EXPECT_TRUE(exact) << exact.error().message;
        if (const char* dump = std::getenv("TERRAIN_IMAGERY_DUMP"); dump && exact) {
            // The frame, the reference and their difference × 8, for a look (rows bottom-up).
            static int dumped = 0;
            std::FILE* f =
                std::fopen((std::string(dump) + std::to_string(dumped++) + ".ppm").c_str(), "wb");
            std::fprintf(f, "P6 %d %d 255\n", 3 * kWidth, kHeight);
            const auto& ref = exact.value().referenceRgba;
            for (int y = kHeight - 1; y >= 0; --y)
                for (int x = 0; x < 3 * kWidth; ++x) {
                    const std::size_t i = static_cast<std::size_t>(y) * kWidth + (x % kWidth);
                    for (int k = 0; k < 3; ++k) {
                        const int a = frame.rgba[4 * i + k], b = ref[4 * i + k];
                        const int v = x < kWidth       ? a
                                      : x < 2 * kWidth ? b
                                                       : std::min(255, 8 * std::abs(a - b)) *
                                                             (ref[4 * i + 3] / 255);
                        std::fputc(v, f);
                    }
                }
            std::fclose(f);
        }
        runtime::TerrainStyle other = drawn;
        other.imageryOpacity = {0.0f, 1.0f, 1.0f, 1.0f};
        auto shifted = reference.value()->compare(camera, frame, other);
        EXPECT_TRUE(shifted) << shifted.error().message;
        if (exact) out.exact = std::move(exact).value();
        if (shifted) out.shifted = std::move(shifted).value();
        return out;
    }

    TempFolder m_folder;
    std::filesystem::path m_pyramid;
};

void print(const char* what, const runtime::ImageryFrameComparison& c) {
    std::cout << "[          ] " << what << ": " << c.comparedPixels << " pixels compared, PSNR "
              << c.psnrDb << " dB, worst " << c.maxLevels << " levels, " << c.visiblePixels
              << " pixels over " << runtime::ImageryFrameComparison::kVisibleLevels
              << ", texels per pixel p50 " << c.texelsPerPixelP50
              << " (in 0.5-2: " << c.texelsPerPixelInRange << ")\n";
}

void print(const char* what, const runtime::ImageryTexelsPerPixel& t) {
    std::cout << "[          ] " << what << ": " << t.pixels << " pixels, p5 " << t.p5 << ", p50 "
              << t.p50 << ", p95 " << t.p95 << " (in 0.5-2: " << t.inRange << ")\n";
}

// Low over the hills looking across them: patches and imagery of every level, near and far.
runtime::Camera acrossTheHills(const runtime::TerrainGeometry& g) {
    return lookingAt(kWidth, kHeight, {g.worldAtFraction(0.3, 0.9), 440.0},
                     {g.worldAtFraction(0.32, 0.86), 300.0});
}

// Straight down from high up: the whole terrain, its imagery minified.
runtime::Camera fromAbove(const runtime::TerrainGeometry& g) {
    return lookingAt(kWidth, kHeight, {g.worldAtFraction(0.5, 0.5), 9000.0},
                     {g.worldAtFraction(0.5, 0.501), 300.0});
}

TEST_F(ImageryReferenceTest, TheDrapedDrawAgreesWithTheReferenceAndAShiftedLayerDoesNot) {
    using Pose = runtime::Camera (*)(const runtime::TerrainGeometry&);
    for (const auto& [name, pose] :
         {std::pair<const char*, Pose>{"across the hills", acrossTheHills},
          std::pair<const char*, Pose>{"from above", fromAbove}}) {
        SCOPED_TRACE(name);
        const Compared c = drapeAndCompare(pose);
        print(name, c.exact);
        print("  against the shifted layer", c.shifted);
        print("  texels per pixel the GPU drew", c.gpu);
        EXPECT_GT(c.exact.comparedPixels, std::uint64_t{kWidth * kHeight / 8});
        // Measured on llvmpipe: 53 and 55 dB, 38 pixels over 8 levels (at silhouettes, where
        // the GPU's derivatives come from the triangle and the reference's from neighbours).
        EXPECT_GE(c.exact.psnrDb, 45.0);
        EXPECT_LE(c.exact.visiblePixels, c.exact.comparedPixels / 500);
        // One texel east: the fast wave moves by a third of its period (27 and 42 dB).
        EXPECT_LE(c.shifted.psnrDb, c.exact.psnrDb - 10.0);
        // Close, it differs visibly wherever the fast wave is sharp (two thirds of the view).
        if (pose == acrossTheHills) {
            EXPECT_GT(c.shifted.visiblePixels, c.shifted.comparedPixels / 4);
        }
        // The level the streamed draw sampled is the one the reference's ideal filter reads.
        EXPECT_GT(c.gpu.pixels, c.exact.comparedPixels / 2);
        EXPECT_NEAR(c.gpu.p50, c.exact.texelsPerPixelP50, 0.1 * c.exact.texelsPerPixelP50);
    }
}

}  // namespace
}  // namespace terrain::test
