// The shared DEMs on the globe (issue 15's acceptance): ETOPO20's whole planet, the 90 m
// Rainier tile and the 30 m N57E011 tile build into one globe pyramid, and it is flown from
// orbit down to Rainier: every settled frame within ε + 0.05 px of the sources'
// full-resolution surface (ScreenSpaceError.h, GlobeTruth.h), no hole where the ground must be, one
// draw.
#include "GlTestFixture.h"
#include "SharedData.h"
#include "TempFolder.h"
#include "terrain/build/GlobePyramidBuilder.h"
#include "terrain/build/GlobeSourceSurface.h"
#include "terrain/dem/OpenDem.h"
#include "terrain/gl/Framebuffer.h"
#include "terrain/runtime/GlobeCamera.h"
#include "terrain/runtime/GlobeTruth.h"
#include "terrain/runtime/ScreenSpaceError.h"
#include "terrain/runtime/TerrainSession.h"

#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <iostream>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

namespace terrain::runtime {
namespace {

class GlobeSharedDataTest : public test::GlTest {};

TEST_F(GlobeSharedDataTest, EtopoRainierAndN57E011FlyFromOrbitToRainierWithinEpsilon) {
    TERRAIN_SHARED_DATA_OR_SKIP(etopo, "etopo20_global.nc");
    TERRAIN_SHARED_DATA_OR_SKIP(rainier, "srtm3_n46w122_rainier.tif");
    TERRAIN_SHARED_DATA_OR_SKIP(sweden, "srtm/N57E011.hgt");
    std::vector<std::unique_ptr<io::DemReader>> readers;
    std::vector<io::DemReader*> sources;
    for (const auto& path : {etopo, rainier, sweden}) {
        auto opened = io::openDem({path.string()}, {});
        ASSERT_TRUE(opened) << opened.error().message;
        sources.push_back(opened.value().get());
        readers.push_back(std::move(opened).value());
    }
    test::TempFolder temp;
    const auto pyramid = temp.path() / "earth.pyramid";
    auto built = io::buildGlobePyramid(sources, pyramid);
    ASSERT_TRUE(built) << built.error().message;
    EXPECT_GE(built.value().manifest.globe->faceFinestLevel, 11);
    auto surface = io::GlobeSourceSurface::read(sources, std::uint64_t{2} << 30,
                                                built.value().manifest.layout.patchQuads());
    ASSERT_TRUE(surface) << surface.error().message;
    GlobeTruth sourceTruth(
        [&surface](double latitude, double longitude) -> Result<std::pair<double, double>> {
            return surface.value().heightsAt(latitude, longitude);
        });

    constexpr double kErrorPx = 2.0;
    TerrainSessionOptions options;
    options.streaming.gpuLayers = 1024;
    options.streaming.cpuCacheBytes = std::size_t{256} << 20;
    options.lod.errorPx = kErrorPx;
    auto opened = TerrainSession::open(pyramid, options);
    ASSERT_TRUE(opened) << opened.error().message;
    TerrainSession& session = *opened.value();
    constexpr int kWidth = 320, kHeight = 180;
    auto framebuffer = gl::Framebuffer::create(kWidth, kHeight, "shared globe");
    ASSERT_TRUE(framebuffer) << framebuffer.error().message;
    const std::vector<std::pair<std::string, GlobePose>> poses{
        {"the whole Earth from 20,000 km", {{40.0, -100.0, 20e6}, 0.0, -90.0}},
        {"the Pacific Northwest from 400 km", {{46.5, -121.5, 400e3}, 0.0, -60.0}},
        {"Rainier from 30 km", {{46.85, -121.76, 30e3}, 0.0, -90.0}},
        {"Rainier from Paradise, 30 m up", {{46.786, -121.735, 1681.0}, 350.0, 6.0}},
        {"N57E011 from 10 km", {{57.5, 11.5, 10e3}, 45.0, -40.0}},
    };
    for (const auto& [name, pose] : poses) {
        SCOPED_TRACE(name);
        Camera camera;
        camera.viewportWidth = kWidth;
        camera.viewportHeight = kHeight;
        camera.fovY = 50.0 * std::numbers::pi / 180.0;
        placeOnGlobe(camera, pose);
        std::vector<float> depth[2];
        TerrainDrawStats drawn;
        for (int skirts = 1; skirts >= 0; --skirts) {
            ASSERT_TRUE(session.settle(camera, std::chrono::seconds(120)));
            session.beginFrame(camera);
            framebuffer.value().clear({0.0f, 0.0f, 0.0f, 1.0f}, 0.0f);
            glBindFramebuffer(GL_FRAMEBUFFER, framebuffer.value().id());
            glViewport(0, 0, kWidth, kHeight);
            TerrainStyle style;
            style.skirts = skirts != 0;
            drawn = session.draw(camera, style);
            glBindFramebuffer(GL_FRAMEBUFFER, 0);
            FrameTelemetry ignored;
            session.endFrame(ignored);
            depth[skirts] = framebuffer.value().readDepth();
        }
        EXPECT_EQ(drawn.drawCalls, 1);
        auto measured =
            measureScreenSpaceError(camera, depth[1], depth[0], {}, sourceTruth, kErrorPx);
        ASSERT_TRUE(measured) << measured.error().message;
        const ScreenSpaceErrorStats& error = measured.value();
        std::cout << name << ": " << session.lodStats().drawn << " patches, measured error max "
                  << error.maxPx << " px, p99 " << error.p99Px << " px over " << error.pixels
                  << " pixels\n";
        EXPECT_GT(error.pixels, 1000u);
        EXPECT_LE(error.maxPx, kErrorPx + 0.05);
    }
}

}  // namespace
}  // namespace terrain::runtime
