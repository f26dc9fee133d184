// The globe end to end (TerrainSession on a globe pyramid: streaming, the LOD quadtree on the
// globe's surface, the draw) on the stability cases of a globe (DESIGN.md, "The globe"): the
// whole Earth from 20,000 km, an oblique view from low orbit, straight down at both poles, over
// a cube corner, across the antimeridian, 1 m above the highest point looking at the horizon,
// below sea level. For each, settled:
//  - no hole: every pixel whose view ray meets the ellipsoid lowered below the deepest drawn
//    point shows terrain, not the clear colour (the terrain lies above that ellipsoid);
//  - horizon culling never removes a visible pixel: the images with it on and off are equal;
//  - every drawn patch's skirt depth and error are finite (else no skirt is drawn);
//  - one draw call, data patches drawn where the data is;
//  - against the globe reference image (ReferenceRenderer, GlobeReferenceScene): no crack, PSNR at
//  ε = 1 px
//    and below it at ε = 8 px, and no hole in the reference itself.
#include "GeographicFunctionDem.h"
#include "GlTestFixture.h"
#include "GlobeTestSources.h"
#include "TempFolder.h"
#include "terrain/build/GlobePyramidBuilder.h"
#include "terrain/build/GlobeSourceSurface.h"
#include "terrain/gl/Framebuffer.h"
#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/pyramid/PyramidReader.h"
#include "terrain/runtime/FrameImages.h"
#include "terrain/runtime/GlobeCamera.h"
#include "terrain/runtime/GlobeReferenceScene.h"
#include "terrain/runtime/GlobeTruth.h"
#include "terrain/runtime/ImageComparison.h"
#include "terrain/runtime/ReferenceRenderer.h"
#include "terrain/runtime/ScreenProjection.h"
#include "terrain/runtime/ScreenSpaceError.h"
#include "terrain/runtime/TerrainSession.h"

#include <epoxy/gl.h>
#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <numbers>
#include <string>
#include <vector>

namespace terrain::runtime {
namespace {

constexpr int kWidth = 240;
constexpr int kHeight = 160;
constexpr double kDegree = std::numbers::pi / 180.0;

struct Pose {
    std::string name;
    GlobePose pose;
};

class GlobeSessionTest : public test::GlTest {
protected:
    static void SetUpTestSuite() {
        test::GlTest::SetUpTestSuite();
        s_folder = std::make_unique<test::TempFolder>();
        s_pyramid = s_folder->path() / "planet.pyramid";
        auto built = test::buildReliefPlanet(s_pyramid);
        ASSERT_TRUE(built) << built.error().message;
        s_maxHeight = built.value().manifest.statistics.maxHeight;
        s_minHeight = built.value().manifest.statistics.minHeight;
    }
    static void TearDownTestSuite() {
        s_folder.reset();
        test::GlTest::TearDownTestSuite();
    }

    static std::vector<Pose> poses() {
        return {
            {"the whole Earth from 20,000 km", {{20.0, 30.0, 20e6}, 0.0, -90.0}},
            {"oblique from 1,000 km", {{40.0, 10.0, 1e6}, 0.0, -20.0}},
            {"straight down at the north pole", {{90.0, 0.0, 50e3}, 0.0, -90.0}},
            {"straight down at the south pole", {{-90.0, 0.0, 50e3}, 0.0, -90.0}},
            {"over a cube corner", {{35.26439, 45.0, 20e3}, 30.0, -45.0}},
            {"across the antimeridian", {{0.0, 179.99, 8e3}, 90.0, -30.0}},
            {"1 m above the highest point, at the horizon",
             {{0.0, 0.0, s_maxHeight + 1.0}, 45.0, 0.0}},
            {"below sea level", {{-12.86, 0.0, -600.0}, 0.0, -10.0}},
        };
    }

    // Renders `pose` settled at the session's ε; returns the RGBA image (and the depth, if
    // asked).
    std::vector<std::uint8_t> render(TerrainSession& session, gl::Framebuffer& framebuffer,
                                     const Camera& camera, LodUpdateStats* stats = nullptr,
                                     TerrainDrawStats* drawn = nullptr, bool skirts = true,
                                     std::vector<float>* depth = nullptr) {
        EXPECT_TRUE(session.settle(camera, std::chrono::seconds(60)));
        const LodUpdateStats& lod = session.beginFrame(camera);
        if (stats != nullptr) *stats = lod;
        framebuffer.clear({1.0f, 0.0f, 1.0f, 1.0f}, 0.0f);
        glBindFramebuffer(GL_FRAMEBUFFER, framebuffer.id());
        glViewport(0, 0, kWidth, kHeight);
        TerrainStyle style;
        style.skyColor = {1.0f, 0.0f, 1.0f};
        style.skirts = skirts;
        const TerrainDrawStats d = session.draw(camera, style);
        if (drawn != nullptr) *drawn = d;
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        FrameTelemetry ignored;
        session.endFrame(ignored);
        if (depth != nullptr) *depth = framebuffer.readDepth();
        return framebuffer.readColorRgba8();
    }

    // A session with room for every patch of the planet.
    static TerrainSessionOptions sessionOptions() {
        TerrainSessionOptions options;
        options.streaming.gpuLayers = 1024;
        options.streaming.cpuCacheBytes = std::size_t{256} << 20;
        return options;
    }
    // Below the deepest point the terrain can be drawn at: its lowest sample, minus the sag
    // of the coarsest flat triangles (a level-0 face of 33 samples, 5 km).
    static double lowerEllipsoidM() {
        return -s_minHeight + globe::flatTriangleErrorBound(globe::maxSampleSpacing(0, 32)) + 100.0;
    }

    static inline std::unique_ptr<test::TempFolder> s_folder;
    static inline std::filesystem::path s_pyramid;
    static inline double s_maxHeight = 0.0;
    static inline double s_minHeight = 0.0;
};

Camera cameraFor(const GlobePose& pose) {
    Camera camera;
    camera.viewportWidth = kWidth;
    camera.viewportHeight = kHeight;
    camera.fovY = 50.0 * kDegree;
    placeOnGlobe(camera, pose);
    return camera;
}

// Whether pixel (x, y)'s ray from the camera meets the ellipsoid lowered by `lowerM`.
bool rayMeetsLoweredEllipsoid(const Camera& camera, int x, int y, double lowerM) {
    const glm::dmat4 inverse = glm::inverse(camera.relativeViewProjection());
    const glm::dvec3 direction =
        glm::normalize(unprojectPixel(inverse, kWidth, kHeight, x, y, 0.5));
    const glm::dvec3 radii(globe::Wgs84::kEquatorialRadius - lowerM,
                           globe::Wgs84::kEquatorialRadius - lowerM,
                           globe::Wgs84::kPolarRadius - lowerM);
    const glm::dvec3 o = camera.position / radii;
    const glm::dvec3 d = direction / radii;
    const double a = glm::dot(d, d), b = glm::dot(o, d), c = glm::dot(o, o) - 1.0;
    const double discriminant = b * b - a * c;
    if (discriminant < 0.0) return false;
    return (-b + std::sqrt(discriminant)) / a > 0.0 && (c > 0.0 ? -b > 0.0 : true);
}

// Whether pixel (x, y) must show the ground: its ray and its neighbours' meet the ellipsoid
// lowered by `lowerM` (the limb's own pixel is the rasteriser's to decide).
bool groundMustShow(const Camera& camera, int x, int y, double lowerM) {
    for (int k = 0; k < 9; ++k)
        if (!rayMeetsLoweredEllipsoid(camera, std::clamp(x + k % 3 - 1, 0, kWidth - 1),
                                      std::clamp(y + k / 3 - 1, 0, kHeight - 1), lowerM))
            return false;
    return true;
}

bool isClearColour(const std::vector<std::uint8_t>& image, int x, int y) {
    const std::uint8_t* p = &image[static_cast<std::size_t>(4 * (y * kWidth + x))];
    return p[0] == 255 && p[1] == 0 && p[2] == 255;
}

TEST_F(GlobeSessionTest, EveryStabilityCaseHasNoHoleAndHorizonCullingChangesNoPixel) {
    auto opened = TerrainSession::open(s_pyramid, sessionOptions());
    ASSERT_TRUE(opened) << opened.error().message;
    TerrainSession& session = *opened.value();
    auto framebuffer = gl::Framebuffer::create(kWidth, kHeight, "globe test");
    ASSERT_TRUE(framebuffer) << framebuffer.error().message;
    const double lowerM = lowerEllipsoidM();
    for (const Pose& p : poses()) {
        SCOPED_TRACE(p.name);
        const Camera camera = cameraFor(p.pose);
        LodOptions lod;
        lod.horizonCulling = true;
        session.setLodOptions(lod);
        LodUpdateStats culled;
        TerrainDrawStats drawn;
        const std::vector<std::uint8_t> withCulling =
            render(session, framebuffer.value(), camera, &culled, &drawn);
        lod.horizonCulling = false;
        session.setLodOptions(lod);
        LodUpdateStats all;
        const std::vector<std::uint8_t> without =
            render(session, framebuffer.value(), camera, &all);
        EXPECT_EQ(drawn.drawCalls, 1);
        EXPECT_GT(culled.drawn - culled.drawnBare, 0u) << "no data patch drawn";
        // A face's root tile stores λ(d) = +∞ where its chords sag more than a half holds:
        // a skirt depth taken from it was infinite, every skirt a vertex at infinity (none
        // drawn), and the gaps between patches showed the far side or the sky.
        for (const PatchDraw& draw : session.draws()) {
            EXPECT_TRUE(std::isfinite(draw.skirtDepthM) && std::isfinite(draw.errorM))
                << "patch level " << draw.id.level << ": skirt depth " << draw.skirtDepthM
                << " m, error " << draw.errorM << " m";
        }
        EXPECT_LE(culled.drawn, all.drawn);
        int differing = 0, holes = 0, checked = 0;
        for (int y = 0; y < kHeight; ++y) {
            for (int x = 0; x < kWidth; ++x) {
                const std::size_t i = static_cast<std::size_t>(4 * (y * kWidth + x));
                differing += std::equal(&withCulling[i], &withCulling[i] + 4, &without[i]) ? 0 : 1;
                if (!groundMustShow(camera, x, y, lowerM)) continue;
                ++checked;
                holes += isClearColour(withCulling, x, y) ? 1 : 0;
            }
        }
        std::cout << p.name << ": " << culled.drawn << " patches (" << culled.drawnBare
                  << " bare), " << culled.horizonCulled << " behind the horizon; " << checked
                  << " pixels must be ground\n";
        EXPECT_EQ(differing, 0) << "horizon culling changed pixels";
        EXPECT_EQ(holes, 0) << "of " << checked << " pixels that must show the ground";
    }
}

// The measured screen-space error (ScreenSpaceError.h, GlobeTruth.h) against the sources'
// full-resolution surface on every stability case, at ε = 1, 2 and 4 px: the drawn surface
// stays within ε + kRasterTolerancePx on every pose (the worst error two adjacent pixels show).
// Water pixels of an image (the shaded view's sea is blue; land is green, brown or grey).
std::size_t waterPixels(const std::vector<std::uint8_t>& image) {
    std::size_t water = 0;
    for (std::size_t i = 0; i + 3 < image.size(); i += 4) {
        const bool clear = image[i] == 255 && image[i + 1] == 0 && image[i + 2] == 255;
        water += !clear && int{image[i + 2]} > int{image[i]} + 24 ? 1 : 0;
    }
    return water;
}

// A pyramid whose sources state their sea 600 m above their zero (heights above the
// ellipsoid, say): more of the planet is drawn as water, and the sea floor in view is as
// before.
TEST_F(GlobeSessionTest, AStatedSeaLevelFloodsWhatLiesBelowIt) {
    const test::TempFolder folder;
    const std::filesystem::path flooded = folder.path() / "flooded.pyramid";
    std::filesystem::copy(s_pyramid, flooded, std::filesystem::copy_options::recursive);
    auto manifest = io::readManifest(flooded);
    ASSERT_TRUE(manifest) << manifest.error().message;
    manifest.value().globe->seaLevelM = 600.0;
    ASSERT_TRUE(io::writeManifest(flooded, manifest.value()));
    auto framebuffer = gl::Framebuffer::create(kWidth, kHeight, "globe test");
    ASSERT_TRUE(framebuffer) << framebuffer.error().message;
    const Camera camera = cameraFor({{20.0, 30.0, 20e6}, 0.0, -90.0});
    std::size_t water[2] = {0, 0};
    for (int k = 0; k < 2; ++k) {
        auto opened = TerrainSession::open(k == 0 ? s_pyramid : flooded, sessionOptions());
        ASSERT_TRUE(opened) << opened.error().message;
        water[k] = waterPixels(render(*opened.value(), framebuffer.value(), camera));
    }
    std::cout << "[          ] water pixels from 20,000 km: " << water[0] << " at sea level 0, "
              << water[1] << " at 600 m\n";
    EXPECT_GT(water[0], 0u);
    EXPECT_GT(water[1], water[0] + water[0] / 5);
}

TEST_F(GlobeSessionTest, MeasuredErrorStaysWithinEpsilonOnEveryStabilityCase) {
    test::GeographicFunctionDem source(-180.0, 90.0, 720, 360, 0.5, 0.5, test::reliefPlanet);
    io::DemReader* const sources[] = {&source};
    auto surface = io::GlobeSourceSurface::read(sources, std::uint64_t{1} << 30, 32);
    ASSERT_TRUE(surface) << surface.error().message;
    GlobeTruth sourceTruth(
        [&surface](double latitude, double longitude) -> Result<std::pair<double, double>> {
            return surface.value().heightsAt(latitude, longitude);
        });
    auto opened = TerrainSession::open(s_pyramid, sessionOptions());
    ASSERT_TRUE(opened) << opened.error().message;
    TerrainSession& session = *opened.value();
    auto framebuffer = gl::Framebuffer::create(kWidth, kHeight, "globe accuracy");
    ASSERT_TRUE(framebuffer) << framebuffer.error().message;
    constexpr double kRasterTolerancePx = 0.05;
    for (const double errorPx : {1.0, 2.0, 4.0}) {
        LodOptions lod;
        lod.errorPx = errorPx;
        session.setLodOptions(lod);
        for (const Pose& p : poses()) {
            SCOPED_TRACE(p.name + ", ε = " + std::to_string(errorPx));
            const Camera camera = cameraFor(p.pose);
            std::vector<float> withSkirts, withoutSkirts;
            render(session, framebuffer.value(), camera, nullptr, nullptr, true, &withSkirts);
            render(session, framebuffer.value(), camera, nullptr, nullptr, false, &withoutSkirts);
            auto measured = measureScreenSpaceError(camera, withSkirts, withoutSkirts, {},
                                                    sourceTruth, errorPx);
            ASSERT_TRUE(measured) << measured.error().message;
            const ScreenSpaceErrorStats& stats = measured.value();
            std::cout << "ε = " << errorPx << ", " << p.name << ": " << stats.pixels
                      << " pixels, max " << stats.maxPx << " px, p99 " << stats.p99Px
                      << " px, mean " << stats.meanPx << " px\n";
            EXPECT_GT(stats.pixels, 1000u);
            EXPECT_LE(stats.maxPx, errorPx + kRasterTolerancePx);
        }
    }
}

// The globe reference renderer (every finest sample a vertex, no LOD) against the LOD on every
// stability case: the LOD leaves no pixel uncovered that the reference draws (no crack, no
// hole), its image is close to the reference at ε = 1 px and further from it at ε = 8 px, and
// the reference itself has no hole where the ground must be.
TEST_F(GlobeSessionTest, EveryStabilityCaseMatchesTheGlobeReference) {
    auto opened = TerrainSession::open(s_pyramid, sessionOptions());
    ASSERT_TRUE(opened) << opened.error().message;
    TerrainSession& session = *opened.value();
    auto pyramid = io::PyramidReader::open(s_pyramid);
    ASSERT_TRUE(pyramid) << pyramid.error().message;
    auto reference =
        ReferenceRenderer::create(std::make_unique<GlobeReferenceScene>(pyramid.value()));
    ASSERT_TRUE(reference) << reference.error().message;
    auto lodTarget = gl::Framebuffer::create(kWidth, kHeight, "globe LOD");
    auto referenceTarget =
        gl::Framebuffer::createWithFloatAttachment(kWidth, kHeight, "globe reference");
    ASSERT_TRUE(lodTarget && referenceTarget);
    const double lowerM = lowerEllipsoidM();
    const std::array<std::uint8_t, 3> clear{255, 0, 255};
    double psnrFine = 0.0, psnrCoarse = 0.0;
    for (const Pose& p : poses()) {
        SCOPED_TRACE(p.name);
        const Camera camera = cameraFor(p.pose);
        referenceTarget.value().clear({1.0f, 0.0f, 1.0f, 1.0f}, 0.0f);
        glBindFramebuffer(GL_FRAMEBUFFER, referenceTarget.value().id());
        glViewport(0, 0, kWidth, kHeight);
        ReferenceStyle style;
        style.skyColor = {1.0f, 0.0f, 1.0f};
        auto drawn = reference.value().draw(camera, style);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        ASSERT_TRUE(drawn) << drawn.error().message;
        const FrameImages truth = readFrameImages(referenceTarget.value());

        int holes = 0, checked = 0;
        for (int y = 0; y < kHeight; ++y) {
            for (int x = 0; x < kWidth; ++x) {
                if (!groundMustShow(camera, x, y, lowerM)) continue;
                ++checked;
                holes += truth.drawn(static_cast<std::size_t>(y * kWidth + x)) ? 0 : 1;
            }
        }
        EXPECT_EQ(holes, 0) << "the reference leaves " << holes << " of " << checked
                            << " ground pixels empty";

        double psnr[2] = {0.0, 0.0};
        for (int i = 0; i < 2; ++i) {
            const double errorPx = i == 0 ? 1.0 : 8.0;
            LodOptions lodOptions;
            lodOptions.errorPx = errorPx;
            session.setLodOptions(lodOptions);
            FrameImages lod;
            lod.width = kWidth;
            lod.height = kHeight;
            lod.rgba =
                render(session, lodTarget.value(), camera, nullptr, nullptr, true, &lod.depth);
            const UncoveredPixels uncovered = countUncoveredPixels(lod, truth, clear);
            EXPECT_EQ(uncovered.cracks.size(), 0u) << "at ε = " << errorPx;
            psnr[i] = compareImages(lod.rgba, truth.rgba).psnrDb;
        }
        std::cout << p.name << ": reference " << drawn.value().tiles << " regions, "
                  << drawn.value().triangles << " triangles; PSNR " << psnr[0] << " dB at ε = 1, "
                  << psnr[1] << " dB at ε = 8\n";
        EXPECT_GE(psnr[0], 30.0);
        psnrFine += psnr[0];
        psnrCoarse += psnr[1];
    }
    EXPECT_GT(psnrFine, psnrCoarse) << "the reference does not tell ε = 1 from ε = 8";

    // Past its limit the reference stops and says its image is partial.
    const Camera whole = cameraFor(poses().front().pose);
    glBindFramebuffer(GL_FRAMEBUFFER, referenceTarget.value().id());
    auto limited = reference.value().draw(whole, ReferenceStyle{}, 10);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    ASSERT_TRUE(limited) << limited.error().message;
    EXPECT_FALSE(limited.value().complete);
    EXPECT_LE(limited.value().tiles, 10u);
}

}  // namespace
}  // namespace terrain::runtime
