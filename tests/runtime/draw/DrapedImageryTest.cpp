// Imagery draped by the terrain draw (issue 47; runtime/lod ImagerySelection.h,
// shaders/terrain_imagery.glsl): tiles whose texels are a known function of the ground's
// position, generated for whichever tiles the selection lists, are drawn where the ground is.
// Every terrain pixel's colour is compared with the function at the point the depth buffer
// puts under it: a texel offset, a flipped axis, a border read from the wrong side or a
// wrong ancestor mapping anywhere (at patch, level or tile boundaries) shows as a colour
// that belongs elsewhere.
#include "AccuracyScenes.h"
#include "GlTestFixture.h"
#include "TempFolder.h"
#include "terrain/gl/Framebuffer.h"
#include "terrain/gl/Texture.h"
#include "terrain/runtime/ImagerySelection.h"
#include "terrain/runtime/ImageryTexelsPerPixel.h"
#include "terrain/runtime/PlaneSurface.h"

#include <epoxy/gl.h>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat4x4.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <iostream>
#include <numbers>
#include <optional>
#include <unordered_map>

namespace terrain::test {
namespace {

constexpr int kWidth = 320;
constexpr int kHeight = 240;
constexpr double kWaveM = 41.0;  // the finest pattern's wavelength

/// The imagery's colour at world (x, y), sRGB-encoded in 0 … 1: slow waves in red and
/// green, a fast one (kWaveM) in blue.
glm::dvec3 groundColour(double x, double y) {
    const double tau = 2.0 * std::numbers::pi;
    return {0.5 + 0.4 * std::sin(tau * x / 613.0), 0.5 + 0.4 * std::sin(tau * y / 419.0),
            // Across (1, 2): neither along nor across a texel's diagonal, so a shift of the
            // texel grid along either axis or both shows in it.
            0.5 + 0.4 * std::sin(tau * (x + 2.0 * y) / (std::sqrt(5.0) * kWaveM))};
}

/// Every tile of one layer, down to `finestLevel`, generated from groundColour the first
/// time the selection asks for it (with its border from the same function and its mips
/// averaged by GL), on the next free layer of one texture array. `residentUpTo` limits the
/// levels made resident (the others are wanted, never delivered).
class GeneratedImagery final : public runtime::ImageryResidency {
public:
    GeneratedImagery(const runtime::TerrainGeometry& geometry, int finestLevel, int residentUpTo)
        : m_geometry(geometry), m_finest(finestLevel), m_residentUpTo(residentUpTo) {
        auto texture = gl::Texture::create2DArray({.internalFormat = GL_SRGB8_ALPHA8,
                                                   .width = io::kImageryTileTexels,
                                                   .height = io::kImageryTileTexels,
                                                   .layers = kLayers,
                                                   .levels = io::kImageryTileMips},
                                                  "test imagery");
        EXPECT_TRUE(texture) << texture.error().message;
        m_texture = std::move(texture).value();
        glTextureParameteri(m_texture.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
        glTextureParameteri(m_texture.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTextureParameteri(m_texture.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTextureParameteri(m_texture.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    }

    const gl::Texture& texture() const { return m_texture; }
    int tilesMade() const { return static_cast<int>(m_layerOf.size()); }
    /// Mips of every tile made so far (GL's average of each 2 × 2).
    void finishMips() { glGenerateTextureMipmap(m_texture.id()); }

    int imageryLayerCount() const override { return 1; }
    std::optional<int> gpuLayer(int, const io::PatchId& id) override {
        if (id.level > m_residentUpTo) return std::nullopt;
        const auto found = m_layerOf.find(id);
        if (found != m_layerOf.end()) return found->second;
        const int layer = static_cast<int>(m_layerOf.size());
        EXPECT_LT(layer, kLayers) << "more tiles than the test's texture holds";
        if (layer >= kLayers) return std::nullopt;
        m_layerOf.emplace(id, layer);
        make(id, layer);
        return layer;
    }
    const io::ImageryTileInfo* tileInfo(int, const io::PatchId& id) const override {
        if (id.level > m_residentUpTo || !m_layerOf.contains(id)) return nullptr;
        return id.level < m_finest ? &m_inner : &m_leaf;
    }
    void want(int, const io::PatchId&, float) override {}
    bool hasFailed(int, const io::PatchId&) const override { return false; }

private:
    static constexpr int kLayers = 400;

    void make(const io::PatchId& id, int layer) {
        std::vector<std::uint8_t> rgba(io::kImageryTileBytes);
        for (int j = 0; j < io::kImageryTileTexels; ++j) {
            for (int i = 0; i < io::kImageryTileTexels; ++i) {
                const io::PlanarSamplePoint p =
                    io::planarImageryPoint(m_geometry.layout(), id, io::imageryPatchLocal(i + 0.5),
                                           io::imageryPatchLocal(j + 0.5));
                const glm::dvec2 world = m_geometry.worldOfSample(p.column, p.row);
                const glm::dvec3 c = groundColour(world.x, world.y);
                std::uint8_t* texel = &rgba[(static_cast<std::size_t>(j) * io::kImageryTileTexels +
                                             static_cast<std::size_t>(i)) *
                                            4];
                for (int k = 0; k < 3; ++k)
                    texel[k] = static_cast<std::uint8_t>(std::lround(c[k] * 255.0));
                texel[3] = 255;
            }
        }
        m_texture.upload({.level = 0,
                          .x = 0,
                          .y = 0,
                          .layer = layer,
                          .width = io::kImageryTileTexels,
                          .height = io::kImageryTileTexels,
                          .layers = 1},
                         GL_RGBA, GL_UNSIGNED_BYTE, std::as_bytes(std::span(rgba)));
    }

    const runtime::TerrainGeometry& m_geometry;
    int m_finest;
    int m_residentUpTo;
    gl::Texture m_texture;
    std::unordered_map<io::PatchId, int, io::PatchIdHash> m_layerOf;
    io::ImageryTileInfo m_inner{true, 0xF, true};
    io::ImageryTileInfo m_leaf{true, 0, true};
};

struct DrapeCheck {
    int compared = 0;         ///< terrain pixels whose footprint is well under the finest wave
    double worstError = 0.0;  ///< largest channel difference, 0 … 255
    int tiles = 0;
    /// Per pixel (rows bottom-up), when drape() was asked for them: the texels per pixel the
    /// GPU drew (TerrainStyle::imageryTexelsPerPixel; 0 without imagery), and those expected
    /// of the level the selection's rule picks for the pixel's footprint on the ground (from
    /// the depth of its neighbours; the finest resident level where it is finer; NaN where
    /// the footprint cannot be told).
    std::vector<float> texelsPerPixel;
    std::vector<double> expectedTexelsPerPixel;
};

class DrapedImageryTest : public GlTest {
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
    }

    /// Draws the settled view of `camera` wearing GeneratedImagery down to `finestLevel`
    /// (resident to `residentUpTo`) and compares it with groundColour under each pixel.
    /// Compares channels [0, channels): 2 leaves the fast wave out, which tiles coarser than
    /// the pixels blur.
    /// With `texelsPerPixel`, draws with the texels-per-pixel variant and fills the check's
    /// figures.
    DrapeCheck drape(const std::function<runtime::Camera(const runtime::TerrainGeometry&)>& pose,
                     int finestLevel, int residentUpTo, int channels = 3,
                     bool texelsPerPixel = false) {
        runtime::TerrainSessionOptions options = roomySessionOptions(1.0);
        options.renderer.imageryTexelsPerPixel = texelsPerPixel;
        auto opened = runtime::TerrainSession::open(m_pyramid, options);
        EXPECT_TRUE(opened) << opened.error().message;
        if (!opened) return {};
        runtime::TerrainSession& session = *opened.value();
        io::PyramidManifest manifest = session.manifest();
        manifest.imagery = {{.name = "waves",
                             .kind = std::string(io::ManifestImageryLayer::kStoredKind),
                             .folder = "imagery/waves",
                             .input = "",
                             .codec = "webp",
                             .coarsestLevel = 0,
                             .finestLevel = finestLevel,
                             .opacity = 1.0}};
        const runtime::TerrainGeometry& geometry = runtime::planeGeometry(session.surface());
        const runtime::Camera camera = pose(geometry);
        EXPECT_TRUE(session.settle(camera, std::chrono::seconds(60)));
        session.beginFrame(camera);
        GeneratedImagery imagery(geometry, finestLevel, residentUpTo);
        runtime::ImagerySelection selection(session.surface(), manifest);
        selection.select(camera, session.draws(), imagery, session.streamer());
        imagery.finishMips();

        auto framebuffer =
            texelsPerPixel ? gl::Framebuffer::createWithFloatAttachment(kWidth, kHeight, "draped")
                           : gl::Framebuffer::create(kWidth, kHeight, "draped");
        EXPECT_TRUE(framebuffer) << framebuffer.error().message;
        framebuffer.value().clear({0.0f, 0.0f, 0.0f, 0.0f}, 0.0f);
        if (texelsPerPixel) framebuffer.value().clearFloatAttachment(0.0f);
        glBindFramebuffer(GL_FRAMEBUFFER, framebuffer.value().id());
        glViewport(0, 0, kWidth, kHeight);
        runtime::TerrainStyle style;
        style.fogDensityPerM = 0.0f;
        style.imageryLighting = false;  // the imagery's own colours
        style.imageryTexelsPerPixel = texelsPerPixel;
        const runtime::DrapedImagery draped{selection, imagery.texture(), 1.0f};
        session.renderer().draw(camera, session.streamer().pool(), session.draws(), style,
                                session.errorPx(), &draped);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        runtime::FrameTelemetry t;
        session.endFrame(t);

        const std::vector<std::uint8_t> colour = framebuffer.value().readColorRgba8();
        const std::vector<float> depth = framebuffer.value().readDepth();
        const glm::dmat4 toRelative = glm::inverse(camera.relativeViewProjection());
        DrapeCheck check;
        std::vector<double> errors(colour.size() / 4, 0.0);
        check.tiles = imagery.tilesMade();
        if (texelsPerPixel) check.texelsPerPixel = framebuffer.value().readFloatAttachment();
        // Each terrain pixel's ground point, from its depth.
        std::vector<std::optional<glm::dvec3>> ground(colour.size() / 4);
        for (int y = 0; y < kHeight; ++y) {
            for (int x = 0; x < kWidth; ++x) {
                const std::size_t i = static_cast<std::size_t>(y) * kWidth + x;
                if (depth[i] <= 0.0f) continue;  // sky
                const glm::dvec4 ndc{2.0 * (x + 0.5) / kWidth - 1.0,
                                     2.0 * (y + 0.5) / kHeight - 1.0, depth[i], 1.0};
                const glm::dvec4 relative = toRelative * ndc;
                ground[i] = camera.position + glm::dvec3(relative) / relative.w;
            }
        }
        for (int y = 0; y + 1 < kHeight; ++y) {
            for (int x = 0; x + 1 < kWidth; ++x) {
                const std::size_t i = static_cast<std::size_t>(y) * kWidth + x;
                const auto& here = ground[i];
                const auto& right = ground[i + 1];
                const auto& up = ground[i + kWidth];
                if (!here || !right || !up) continue;
                if (texelsPerPixel) {
                    check.expectedTexelsPerPixel.resize(colour.size() / 4, std::nan(""));
                    check.expectedTexelsPerPixel[i] = expectedTexelsPerPixel(
                        geometry, *here, *right, *up, finestLevel, residentUpTo);
                }
                // Only pixels whose footprint on the ground (its longer side: the filter's
                // anisotropy follows it) is well under the finest wave: there a footprint's
                // mean colour is the colour at its centre.
                const double footprintM = std::max(glm::length(glm::dvec2(*right - *here)),
                                                   glm::length(glm::dvec2(*up - *here)));
                if (footprintM > kWaveM / 32.0) continue;
                const glm::dvec3 expected = groundColour(here->x, here->y);
                ++check.compared;
                for (int k = 0; k < channels; ++k)
                    errors[i] =
                        std::max(errors[i], std::abs(colour[i * 4 + k] - expected[k] * 255.0));
                check.worstError = std::max(check.worstError, errors[i]);
            }
        }
        if (const char* dump = std::getenv("TERRAIN_DRAPE_DUMP")) {
            // The frame and each pixel's error (red), for a look: rows bottom-up.
            std::FILE* f = std::fopen(dump, "wb");
            std::fprintf(f, "P6 %d %d 255\n", 2 * kWidth, kHeight);
            for (int y = kHeight - 1; y >= 0; --y) {
                for (int x = 0; x < 2 * kWidth; ++x) {
                    const std::size_t i = static_cast<std::size_t>(y) * kWidth + (x % kWidth);
                    std::uint8_t rgb[3] = {colour[i * 4], colour[i * 4 + 1], colour[i * 4 + 2]};
                    if (x >= kWidth) {
                        rgb[0] = static_cast<std::uint8_t>(std::min(255.0, errors[i] * 10.0));
                        rgb[1] = rgb[2] = 0;
                    }
                    std::fwrite(rgb, 1, 3, f);
                }
            }
            std::fclose(f);
        }
        return check;
    }

    /// The texels per pixel of the level ImagerySelection's rule draws for a pixel at `here`
    /// whose neighbours to the right and above lie at `right` and `up` (the footprint on the
    /// map, the larger of the two steps, as the shader takes it from its derivatives): the
    /// level whose texels are no larger than the footprint, no finer than `finestLevel`, and
    /// no finer than `residentUpTo`, whose ancestor is drawn instead.
    static double expectedTexelsPerPixel(const runtime::TerrainGeometry& geometry,
                                         const glm::dvec3& here, const glm::dvec3& right,
                                         const glm::dvec3& up, int finestLevel, int residentUpTo) {
        const double footprintM =
            std::max(glm::length(glm::dvec2(right - here)), glm::length(glm::dvec2(up - here)));
        const io::PyramidLayout& layout = geometry.layout();
        const auto texelM = [&](int level) {
            return std::ldexp(layout.patchQuads() * geometry.sampleSpacing().x,
                              layout.finestLevel() - level) /
                   io::kImageryInteriorTexels;
        };
        const double finestTexels = footprintM / texelM(finestLevel);
        const int wanted = std::max(
            finestLevel - static_cast<int>(std::floor(std::max(std::log2(finestTexels), 0.0))), 0);
        return footprintM / texelM(std::min(wanted, residentUpTo));
    }

    TempFolder m_folder;
    std::filesystem::path m_pyramid;
};

// Low over the hills looking across them: patches of every level, near and far.
runtime::Camera acrossTheHills(const runtime::TerrainGeometry& g) {
    return lookingAt(kWidth, kHeight, {g.worldAtFraction(0.3, 0.9), 440.0},
                     {g.worldAtFraction(0.32, 0.86), 300.0});
}

// Straight down from high up: the whole terrain, its imagery minified.
runtime::Camera fromAbove(const runtime::TerrainGeometry& g) {
    return lookingAt(kWidth, kHeight, {g.worldAtFraction(0.5, 0.5), 9000.0},
                     {g.worldAtFraction(0.5, 0.501), 300.0});
}

TEST_F(DrapedImageryTest, EachPixelShowsTheImageryOfTheGroundUnderIt) {
    // Imagery 8 × finer than the DEM's finest level (2): levels 0 … 5. Within a footprint of
    // a 32nd of the fast wave, filtering (trilinear, in linear light) moves a colour by
    // less than 4 of 255; a texel's offset moves the fast wave by 6.6 / 255 a metre.
    const DrapeCheck check = drape(acrossTheHills, 5, 5);
    std::cout << "[          ] " << check.compared << " pixels compared, " << check.tiles
              << " tiles, worst channel error " << check.worstError << " / 255\n";
    EXPECT_GT(check.compared, kWidth * kHeight / 10);
    EXPECT_LE(check.worstError, 4.0);
}

TEST_F(DrapedImageryTest, ATileNotResidentIsDrawnFromItsAncestorInPlace) {
    // Only levels 0 … 3 arrive: the level-4 and level-5 tiles the view lists are drawn from
    // their level-3 ancestors' quadrants, blurrier but in place (the slow waves agree).
    const DrapeCheck check = drape(acrossTheHills, 5, 3, 2);
    std::cout << "[          ] " << check.compared << " pixels compared, " << check.tiles
              << " tiles, worst channel error (slow waves) " << check.worstError << " / 255\n";
    EXPECT_GT(check.compared, kWidth * kHeight / 10);
    EXPECT_LE(check.worstError, 4.0);
}

/// The read-back figures against the expected ones: their summaries, and the share of pixels
/// with both where they agree within 15 %.
struct TexelsCompared {
    runtime::ImageryTexelsPerPixel drawn;
    runtime::ImageryTexelsPerPixel expected;
    double agreeing = 0.0;
};

TexelsCompared compareTexels(const DrapeCheck& check) {
    TexelsCompared out;
    out.drawn = runtime::summariseTexelsPerPixel(check.texelsPerPixel);
    std::vector<double> expected;
    std::size_t both = 0, agreeing = 0;
    for (std::size_t i = 0; i < check.expectedTexelsPerPixel.size(); ++i) {
        const double e = check.expectedTexelsPerPixel[i];
        if (!(e > 0.0) || !(check.texelsPerPixel[i] > 0.0f)) continue;
        expected.push_back(e);
        ++both;
        agreeing += std::abs(check.texelsPerPixel[i] / e - 1.0) <= 0.15 ? 1 : 0;
    }
    out.expected = runtime::summariseTexelsPerPixel(std::move(expected));
    out.agreeing = both > 0 ? static_cast<double>(agreeing) / static_cast<double>(both) : 0.0;
    return out;
}

void print(const char* what, const TexelsCompared& c) {
    std::cout << "[          ] " << what << ": " << c.drawn.pixels
              << " pixels, texels per pixel drawn p5 " << c.drawn.p5 << ", p50 " << c.drawn.p50
              << ", p95 " << c.drawn.p95 << " (in 0.5-2: " << c.drawn.inRange << "); expected p5 "
              << c.expected.p5 << ", p50 " << c.expected.p50 << ", p95 " << c.expected.p95
              << "; agreeing within 15 %: " << c.agreeing << "\n";
}

TEST_F(DrapedImageryTest, TheTexelsPerPixelReadBackAreThoseOfTheLevelDrawn) {
    // Imagery 32 × finer than the DEM (levels 0 … 7): fine enough for every pixel of both
    // views, so the settled view draws each pixel from the level whose texels are no larger
    // than its footprint: 1 … 2 texels a pixel, more only towards the horizon, where the
    // footprint outgrows level 0's texels (31 m), which nothing coarser replaces.
    const int finest = 7;
    const TexelsCompared close = compareTexels(drape(acrossTheHills, finest, finest, 3, true));
    print("across the hills, settled", close);
    const TexelsCompared far = compareTexels(drape(fromAbove, finest, finest, 3, true));
    print("from above, settled", far);
    // Measured on llvmpipe: close p5 1.04, p50 1.45, 91 % in range (p95 3.4 at the horizon);
    // from above (9 km) 1.34 … 1.38, all in range; 96 and 100 % agreeing pixel by pixel.
    for (const TexelsCompared* c : {&close, &far}) {
        EXPECT_GT(c->drawn.pixels, std::uint64_t{kWidth * kHeight / 4});
        EXPECT_GE(c->drawn.p5, 0.95);
        EXPECT_GE(c->drawn.p50, 1.0);
        EXPECT_LE(c->drawn.p50, 2.0);
        EXPECT_GE(c->drawn.inRange, 0.85);
        // Pixel by pixel the figure is the one the rule gives for the footprint on the ground
        // (apart from where the two choose levels either side of a level's bound).
        EXPECT_NEAR(c->drawn.p50, c->expected.p50, 0.02 * c->expected.p50);
        EXPECT_GE(c->agreeing, 0.9);
    }
    // Only levels 0 … 3 resident: where the view wants finer, the level-3 ancestor is drawn,
    // its texels 2 … 16 times the footprint's, and the figure reads that much smaller
    // (measured: p5 0.27, p50 1.01, 61 % in range, 97 % agreeing).
    const TexelsCompared coarse = compareTexels(drape(acrossTheHills, finest, 3, 2, true));
    print("across the hills, levels 0-3 resident", coarse);
    EXPECT_LE(coarse.drawn.p5, close.drawn.p5 / 2.0);
    EXPECT_LE(coarse.drawn.p50, close.drawn.p50 / 1.3);
    EXPECT_LE(coarse.drawn.inRange, close.drawn.inRange - 0.2);
    EXPECT_NEAR(coarse.drawn.p50, coarse.expected.p50, 0.02 * coarse.expected.p50);
    EXPECT_GE(coarse.agreeing, 0.9);
}

}  // namespace
}  // namespace terrain::test
