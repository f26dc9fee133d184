// GlfwWindowContext: an OpenGL 4.5 core context in a GLFW window, for the interactive
// viewer. GLFW is initialised while at least one window context exists.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/gl/GlContext.h"

#include <memory>
#include <string_view>

struct GLFWwindow;

namespace terrain::gl {

namespace detail {
class GlfwLibrary;
}

struct GlfwWindowOptions {
    bool debugContext = true;
    bool vsync = true;
    bool resizable = true;
    bool visible = true;
    /// Echo debug output to stderr.
    GlDebugEcho echoDebugMessages = GlDebugEcho::FromEnvironment;
};

struct FramebufferSize {
    int width = 0;
    int height = 0;
};

class GlfwWindowContext final : public GlContext {
public:
    /// Opens the window and makes its context current on the calling thread, which must
    /// be the main thread (a GLFW rule). GLFW's own error text ends up in the Error.
    static Result<std::unique_ptr<GlfwWindowContext>> create(int width, int height,
                                                             std::string_view title,
                                                             const GlfwWindowOptions& options = {});

    /// Closes the window. Main thread only.
    ~GlfwWindowContext() override;

    Status makeCurrent() override;
    const GlInfo& info() const override { return m_info; }
    GlDebugLog& debugLog() override { return m_debugLog; }
    const GlDebugLog& debugLog() const override { return m_debugLog; }

    /// The window, for input callbacks and the event loop of the viewer.
    GLFWwindow* window() const { return m_window; }

    /// Presents the back buffer. Render thread only.
    void swapBuffers();

    /// Waits for the display's vertical blank in swapBuffers() (true) or not. The context
    /// must be current. Render thread only.
    void setVsync(bool vsync);

    bool shouldClose() const;

    /// Size of the default framebuffer in pixels (differs from the window size on
    /// high-DPI screens).
    FramebufferSize framebufferSize() const;

private:
    GlfwWindowContext(std::unique_ptr<detail::GlfwLibrary> library, GLFWwindow* window,
                      bool echoDebugMessages);

    std::unique_ptr<detail::GlfwLibrary> m_library;
    GLFWwindow* m_window = nullptr;
    GlInfo m_info;
    GlDebugLog m_debugLog;
};

}  // namespace terrain::gl
