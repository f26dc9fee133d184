// GL contexts: what they report, platform selection, several contexts at once, debug
// output capture, and a clear Error when a window cannot be opened.
#include "GlTestFixture.h"
#include "TestSupport.h"
#include "terrain/gl/Framebuffer.h"
#include "terrain/gl/GlfwWindowContext.h"
#include "terrain/gl/HeadlessGlContext.h"

#include <cstdlib>
#include <string>

namespace terrain::test {
namespace {

class GlContextTest : public GlTest {};

TEST_F(GlContextTest, InfoReportsGl45CoreAndARenderer) {
    const gl::GlInfo& info = context().info();
    EXPECT_TRUE(info.atLeast(4, 5)) << info.version;
    EXPECT_TRUE(info.coreProfile);
    EXPECT_TRUE(info.debugContext);
    EXPECT_FALSE(info.renderer.empty());
    EXPECT_FALSE(info.vendor.empty());
    EXPECT_TRUE(info.glslVersion.starts_with("4.")) << info.glslVersion;
    EXPECT_TRUE(info.platform == "egl-device" || info.platform == "egl-surfaceless")
        << info.platform;
    EXPECT_FALSE(info.platformDetail.empty());
    EXPECT_GE(info.maxTessGenLevel, 64);
    EXPECT_GE(info.maxArrayTextureLayers, 256);
    RecordProperty("renderer", info.renderer);
    RecordProperty("platform", info.platform + ": " + info.platformDetail);
}

TEST_F(GlContextTest, DebugLogCountsErrorsAndNotNotifications) {
    gl::GlDebugLog& log = debugLog();
    glDebugMessageInsert(GL_DEBUG_SOURCE_APPLICATION, GL_DEBUG_TYPE_MARKER, 1,
                         GL_DEBUG_SEVERITY_NOTIFICATION, -1, "a harmless marker");
    EXPECT_EQ(log.errorCount(), 0u);
    EXPECT_GE(log.messageCount(), 1u);

    glDebugMessageInsert(GL_DEBUG_SOURCE_APPLICATION, GL_DEBUG_TYPE_ERROR, 2,
                         GL_DEBUG_SEVERITY_HIGH, -1, "an application error");
    EXPECT_EQ(log.errorCount(), 1u);

    glBindTexture(0x1234, 0);  // a real GL error: invalid texture target
    EXPECT_EQ(log.errorCount(), 2u);
    const auto errors = log.errors();
    ASSERT_EQ(errors.size(), 2u);
    EXPECT_TRUE(contains(errors[0].describe(), "an application error")) << errors[0].describe();
    EXPECT_EQ(errors[1].type, static_cast<GLenum>(GL_DEBUG_TYPE_ERROR));
    EXPECT_TRUE(contains(log.formatErrors(), "an application error"));
    while (glGetError() != GL_NO_ERROR) {
    }

    log.clear();  // the errors above were on purpose
    EXPECT_EQ(log.errorCount(), 0u);
    EXPECT_TRUE(log.messages().empty());
}

TEST(HeadlessGlContext, ForcedSurfacelessPlatform) {
    auto context = gl::HeadlessGlContext::create({.platform = gl::EglPlatform::Surfaceless});
    if (!context) {
        // Only Mesa provides EGL_MESA_platform_surfaceless; the Error must say what failed.
        EXPECT_TRUE(contains(context.error().message, "egl-surfaceless"))
            << context.error().message;
        GTEST_SKIP() << context.error().message;
    }
    EXPECT_EQ(context.value()->info().platform, "egl-surfaceless");
    EXPECT_TRUE(context.value()->info().atLeast(4, 5));
}

TEST(HeadlessGlContext, ForcedDevicePlatform) {
    auto context = gl::HeadlessGlContext::create({.platform = gl::EglPlatform::Device});
    if (!context) {
        EXPECT_TRUE(contains(context.error().message, "egl-device")) << context.error().message;
        GTEST_SKIP() << context.error().message;
    }
    EXPECT_EQ(context.value()->info().platform, "egl-device");
    EXPECT_TRUE(context.value()->info().atLeast(4, 5));
}

TEST(HeadlessGlContext, EnvironmentSelectsThePlatform) {
    ScopedEnv platform("TERRAIN_EGL_PLATFORM", "surfaceless");
    auto context = gl::HeadlessGlContext::create();
    if (!context) {
        EXPECT_TRUE(contains(context.error().message, "surfaceless")) << context.error().message;
        GTEST_SKIP() << context.error().message;
    }
    EXPECT_EQ(context.value()->info().platform, "egl-surfaceless");
}

TEST(HeadlessGlContext, BadEnvironmentValueIsAnError) {
    ScopedEnv platform("TERRAIN_EGL_PLATFORM", "vulkan");
    auto context = gl::HeadlessGlContext::create();
    ASSERT_FALSE(context);
    EXPECT_TRUE(contains(context.error().message, "TERRAIN_EGL_PLATFORM"))
        << context.error().message;
    EXPECT_TRUE(contains(context.error().message, "vulkan")) << context.error().message;
}

TEST(HeadlessGlContext, PlatformNamesParse) {
    EXPECT_EQ(gl::parseEglPlatform("device").value(), gl::EglPlatform::Device);
    EXPECT_EQ(gl::parseEglPlatform("surfaceless").value(), gl::EglPlatform::Surfaceless);
    EXPECT_EQ(gl::parseEglPlatform("auto").value(), gl::EglPlatform::Automatic);
    EXPECT_FALSE(gl::parseEglPlatform("x11"));
}

TEST(HeadlessGlContext, ContextsOnOneDisplaySurviveEachOther) {
    // Both take the same platform, hence the same EGLDisplay: destroying one must leave
    // the display and the other context working.
    auto first = gl::HeadlessGlContext::create();
    ASSERT_TRUE(first) << first.error().message;
    {
        auto second = gl::HeadlessGlContext::create();
        ASSERT_TRUE(second) << second.error().message;
        EXPECT_EQ(second.value()->info().platform, first.value()->info().platform);
    }
    ASSERT_TRUE(first.value()->makeCurrent());
    auto framebuffer = gl::Framebuffer::create(4, 4, "after second context");
    ASSERT_TRUE(framebuffer) << framebuffer.error().message;
    framebuffer.value().clear({0.0f, 1.0f, 0.0f, 1.0f});
    EXPECT_EQ(framebuffer.value().readColorRgba8()[1], 255);
    EXPECT_EQ(first.value()->debugLog().errorCount(), 0u)
        << first.value()->debugLog().formatErrors();
}

TEST(HeadlessGlContext, DestroyingAnotherContextKeepsTheCurrentOne) {
    auto first = gl::HeadlessGlContext::create();
    ASSERT_TRUE(first) << first.error().message;
    auto second = gl::HeadlessGlContext::create();
    ASSERT_TRUE(second) << second.error().message;
    ASSERT_TRUE(first.value()->makeCurrent());
    second.value().reset();  // destroys the second context
    // Still current: GL calls work without another makeCurrent.
    auto framebuffer = gl::Framebuffer::create(2, 2);
    ASSERT_TRUE(framebuffer) << framebuffer.error().message;
    EXPECT_EQ(first.value()->debugLog().errorCount(), 0u)
        << first.value()->debugLog().formatErrors();
}

TEST(GlfwWindowContext, OpensAWindowOrSaysWhyNot) {
    const char* display = std::getenv("DISPLAY");
    const char* wayland = std::getenv("WAYLAND_DISPLAY");
    const bool haveDisplay =
        (display != nullptr && display[0] != '\0') || (wayland != nullptr && wayland[0] != '\0');
    auto window =
        gl::GlfwWindowContext::create(64, 48, "terrain test", {.vsync = false, .visible = false});
    if (!haveDisplay) {
        ASSERT_FALSE(window);
        EXPECT_TRUE(contains(window.error().message, "GLFW")) << window.error().message;
        return;
    }
    ASSERT_TRUE(window) << window.error().message;
    EXPECT_EQ(window.value()->info().platform, "glfw");
    EXPECT_TRUE(window.value()->info().atLeast(4, 5));
    EXPECT_NE(window.value()->window(), nullptr);
    EXPECT_EQ(window.value()->debugLog().errorCount(), 0u)
        << window.value()->debugLog().formatErrors();
}

}  // namespace
}  // namespace terrain::test
