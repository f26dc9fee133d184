// The GL wrappers of terrain::gl on a real context: data round-trips through textures,
// framebuffers and buffers, limits become Errors, handles own their objects, and helpers
// leave pixel-store state as they found it.
#include "GlTestFixture.h"
#include "TestSupport.h"
#include "terrain/gl/Buffer.h"
#include "terrain/gl/Framebuffer.h"
#include "terrain/gl/Query.h"
#include "terrain/gl/Texture.h"
#include "terrain/gl/VertexArray.h"

#include <array>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <span>
#include <string>
#include <vector>

namespace terrain::test {
namespace {

class GlResourceTest : public GlTest {};

/// A distinct byte for every (layer, x, y, channel) so misplaced texels show.
std::uint8_t texelByte(int layer, int x, int y, int channel) {
    return static_cast<std::uint8_t>((layer * 61 + x * 7 + y * 13 + channel * 3) & 0xFF);
}

std::vector<std::uint8_t> makeLayers(int firstLayer, int layers, int width, int height) {
    std::vector<std::uint8_t> bytes;
    for (int layer = firstLayer; layer < firstLayer + layers; ++layer) {
        for (int y = 0; y < height; ++y) {
            for (int x = 0; x < width; ++x) {
                for (int channel = 0; channel < 4; ++channel) {
                    bytes.push_back(texelByte(layer, x, y, channel));
                }
            }
        }
    }
    return bytes;
}

TEST_F(GlResourceTest, Texture2DArrayRoundTripsLayers) {
    constexpr int kWidth = 13;  // odd: rows are not 8-byte aligned
    constexpr int kHeight = 9;
    constexpr int kLayers = 6;
    auto created = gl::Texture::create2DArray(
        {.internalFormat = GL_RGBA8, .width = kWidth, .height = kHeight, .layers = kLayers},
        "round trip");
    ASSERT_TRUE(created) << created.error().message;
    gl::Texture& texture = created.value();
    EXPECT_EQ(texture.target(), static_cast<GLenum>(GL_TEXTURE_2D_ARRAY));
    EXPECT_EQ(texture.layers(), kLayers);

    // Layers 1..3 in one call, layer 5 alone; layers 0 and 4 stay untouched.
    const auto first = makeLayers(1, 3, kWidth, kHeight);
    texture.upload({.layer = 1, .width = kWidth, .height = kHeight, .layers = 3}, GL_RGBA,
                   GL_UNSIGNED_BYTE, std::as_bytes(std::span(first)));
    const auto last = makeLayers(5, 1, kWidth, kHeight);
    texture.upload({.layer = 5, .width = kWidth, .height = kHeight, .layers = 1}, GL_RGBA,
                   GL_UNSIGNED_BYTE, std::as_bytes(std::span(last)));

    for (int layer : {1, 2, 3, 5}) {
        std::vector<std::uint8_t> readBack(static_cast<std::size_t>(kWidth * kHeight * 4));
        texture.readBack({.layer = layer, .width = kWidth, .height = kHeight, .layers = 1}, GL_RGBA,
                         GL_UNSIGNED_BYTE, std::as_writable_bytes(std::span(readBack)));
        EXPECT_EQ(readBack, makeLayers(layer, 1, kWidth, kHeight)) << "layer " << layer;
    }

    // A sub-rectangle of layer 2.
    constexpr int kX = 3;
    constexpr int kY = 2;
    constexpr int kSubWidth = 5;
    constexpr int kSubHeight = 4;
    std::vector<std::uint8_t> sub(static_cast<std::size_t>(kSubWidth * kSubHeight * 4));
    texture.readBack({.x = kX, .y = kY, .layer = 2, .width = kSubWidth, .height = kSubHeight},
                     GL_RGBA, GL_UNSIGNED_BYTE, std::as_writable_bytes(std::span(sub)));
    for (int y = 0; y < kSubHeight; ++y) {
        for (int x = 0; x < kSubWidth; ++x) {
            for (int channel = 0; channel < 4; ++channel) {
                ASSERT_EQ(sub[static_cast<std::size_t>(((y * kSubWidth) + x) * 4 + channel)],
                          texelByte(2, kX + x, kY + y, channel))
                    << "texel " << x << "," << y;
            }
        }
    }
}

TEST_F(GlResourceTest, FloatHeightLayersRoundTripExactly) {
    constexpr int kSize = 7;
    auto created = gl::Texture::create2DArray(
        {.internalFormat = GL_R32F, .width = kSize, .height = kSize, .layers = 2});
    ASSERT_TRUE(created) << created.error().message;
    std::vector<float> heights(kSize * kSize * 2);
    std::iota(heights.begin(), heights.end(), -8848.25f);
    created.value().upload(created.value().wholeLevel(), GL_RED, GL_FLOAT,
                           std::as_bytes(std::span(heights)));
    std::vector<float> readBack(heights.size());
    created.value().readBack(created.value().wholeLevel(), GL_RED, GL_FLOAT,
                             std::as_writable_bytes(std::span(readBack)));
    EXPECT_EQ(readBack, heights);
}

TEST_F(GlResourceTest, TextureLimitsAreErrors) {
    GLint maxLayers = 0;
    glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &maxLayers);
    auto tooManyLayers =
        gl::Texture::create2DArray({.width = 4, .height = 4, .layers = maxLayers + 1}, "pool");
    ASSERT_FALSE(tooManyLayers);
    EXPECT_TRUE(contains(tooManyLayers.error().message, "GL_MAX_ARRAY_TEXTURE_LAYERS"))
        << tooManyLayers.error().message;
    EXPECT_TRUE(contains(tooManyLayers.error().message, "'pool'")) << tooManyLayers.error().message;

    EXPECT_FALSE(gl::Texture::create2D({.width = 0, .height = 4}));
    EXPECT_FALSE(gl::Texture::create2D({.width = 4, .height = 4, .layers = 2}));
    EXPECT_FALSE(gl::Texture::create2D({.width = 4, .height = 4, .levels = 4}));
    EXPECT_TRUE(gl::Texture::create2D({.width = 4, .height = 4, .levels = 3}));
}

TEST_F(GlResourceTest, FramebufferClearRoundTrips) {
    constexpr int kWidth = 33;
    constexpr int kHeight = 17;
    auto created = gl::Framebuffer::create(kWidth, kHeight, "clear test");
    ASSERT_TRUE(created) << created.error().message;
    gl::Framebuffer& framebuffer = created.value();
    EXPECT_EQ(framebuffer.width(), kWidth);
    EXPECT_EQ(framebuffer.height(), kHeight);

    framebuffer.clear({1.0f, 0.5f, 0.0f, 1.0f}, 0.25f);
    const std::vector<std::uint8_t> pixels = framebuffer.readColorRgba8();
    ASSERT_EQ(pixels.size(), static_cast<std::size_t>(kWidth * kHeight * 4));
    for (std::size_t i = 0; i < pixels.size(); i += 4) {
        ASSERT_EQ(pixels[i + 0], 255);
        ASSERT_NEAR(pixels[i + 1], 128, 1);
        ASSERT_EQ(pixels[i + 2], 0);
        ASSERT_EQ(pixels[i + 3], 255);
    }

    std::vector<float> depth(static_cast<std::size_t>(kWidth * kHeight));
    framebuffer.depthTexture().readBack(framebuffer.depthTexture().wholeLevel(), GL_DEPTH_COMPONENT,
                                        GL_FLOAT, std::as_writable_bytes(std::span(depth)));
    for (float value : depth) {
        ASSERT_EQ(value, 0.25f);
    }

    const auto corner = framebuffer.readColorRgba8(kWidth - 2, kHeight - 3, 2, 3);
    EXPECT_EQ(corner.size(), 2u * 3u * 4u);
}

TEST_F(GlResourceTest, FramebufferOfImpossibleSizeIsAnError) {
    auto created = gl::Framebuffer::create(0, 16, "empty");
    ASSERT_FALSE(created);
    EXPECT_TRUE(contains(created.error().message, "framebuffer 'empty'"))
        << created.error().message;
}

TEST_F(GlResourceTest, BufferUploadAndReadBack) {
    std::array<std::uint32_t, 8> initial{};
    std::iota(initial.begin(), initial.end(), 100u);
    gl::Buffer buffer = gl::Buffer::createFrom(std::span<const std::uint32_t>(initial),
                                               GL_DYNAMIC_STORAGE_BIT, "numbers");
    ASSERT_TRUE(buffer.valid());
    EXPECT_EQ(buffer.sizeBytes(), sizeof initial);

    const std::array<std::uint32_t, 2> patch = {7, 9};
    buffer.upload(3 * sizeof(std::uint32_t), std::as_bytes(std::span(patch)));
    std::array<std::uint32_t, 8> readBack{};
    buffer.readBack(0, std::as_writable_bytes(std::span(readBack)));
    EXPECT_EQ(readBack, (std::array<std::uint32_t, 8>{100, 101, 102, 7, 9, 105, 106, 107}));
}

TEST_F(GlResourceTest, HandlesOwnTheirObjects) {
    auto created = gl::Texture::create2D({.width = 4, .height = 4}, "owned");
    ASSERT_TRUE(created);
    const GLuint id = created.value().id();
    EXPECT_EQ(glIsTexture(id), GL_TRUE);

    gl::Texture moved = std::move(created).value();
    EXPECT_EQ(moved.id(), id);
    EXPECT_EQ(glIsTexture(id), GL_TRUE);

    std::array<char, 64> label{};
    GLsizei length = 0;
    glGetObjectLabel(GL_TEXTURE, id, static_cast<GLsizei>(label.size()), &length, label.data());
    EXPECT_EQ(std::string(label.data(), static_cast<std::size_t>(length)), "owned");

    moved = gl::Texture();  // deletes the texture
    EXPECT_EQ(glIsTexture(id), GL_FALSE);

    // release() hands the name back without deleting it.
    GLuint raw = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &raw);
    gl::TextureHandle handle(raw);
    EXPECT_EQ(handle.release(), raw);
    EXPECT_FALSE(handle.valid());
    EXPECT_EQ(glIsTexture(raw), GL_TRUE);
    glDeleteTextures(1, &raw);

    gl::VertexArray vertexArray = gl::VertexArray::create("vao");
    const GLuint vaoId = vertexArray.id();
    {
        gl::VertexArray other = std::move(vertexArray);
        EXPECT_EQ(glIsVertexArray(vaoId), GL_TRUE);
    }
    EXPECT_EQ(glIsVertexArray(vaoId), GL_FALSE);
}

TEST_F(GlResourceTest, PixelTransfersLeavePixelStoreStateAlone) {
    glPixelStorei(GL_UNPACK_ALIGNMENT, 8);
    glPixelStorei(GL_PACK_ALIGNMENT, 2);
    auto created = gl::Texture::create2D({.internalFormat = GL_R8, .width = 3, .height = 3});
    ASSERT_TRUE(created);
    const std::array<std::uint8_t, 9> texels = {1, 2, 3, 4, 5, 6, 7, 8, 9};
    created.value().upload(created.value().wholeLevel(), GL_RED, GL_UNSIGNED_BYTE,
                           std::as_bytes(std::span(texels)));
    std::array<std::uint8_t, 9> readBack{};
    created.value().readBack(created.value().wholeLevel(), GL_RED, GL_UNSIGNED_BYTE,
                             std::as_writable_bytes(std::span(readBack)));
    EXPECT_EQ(readBack, texels);

    GLint unpack = 0;
    GLint pack = 0;
    glGetIntegerv(GL_UNPACK_ALIGNMENT, &unpack);
    glGetIntegerv(GL_PACK_ALIGNMENT, &pack);
    EXPECT_EQ(unpack, 8);
    EXPECT_EQ(pack, 2);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
}

TEST_F(GlResourceTest, QueriesGiveResults) {
    auto timer = gl::Query::create(gl::QueryKind::TimeElapsed, "timer");
    ASSERT_TRUE(timer) << timer.error().message;
    auto framebuffer = gl::Framebuffer::create(8, 8);
    ASSERT_TRUE(framebuffer);
    timer.value().begin();
    framebuffer.value().clear({0.0f, 0.0f, 0.0f, 1.0f});
    timer.value().end();
    // Only that a result arrives: llvmpipe stamps the start of a timer query at the next
    // draw, so timing a lone clear gives a meaningless value there (TessellationTest
    // times a real draw).
    (void)timer.value().waitResult();
    EXPECT_TRUE(timer.value().resultAvailable());

    auto invocations = gl::Query::create(gl::QueryKind::TessEvaluationInvocations);
    EXPECT_EQ(invocations.ok(), gl::Query::isSupported(gl::QueryKind::TessEvaluationInvocations));
}

}  // namespace
}  // namespace terrain::test
