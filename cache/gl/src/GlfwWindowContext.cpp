// GLFW window with an OpenGL 4.5 core (debug) context.
#include "terrain/gl/GlfwWindowContext.h"

#include "terrain/gl/DriverWorkarounds.h"

#include "GlfwLibrary.h"

#include <epoxy/gl.h>

// After epoxy: GLFW must not include GL headers of its own.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <string>

namespace terrain::gl {

Result<std::unique_ptr<GlfwWindowContext>> GlfwWindowContext::create(
    int width, int height, std::string_view title, const GlfwWindowOptions& options) {
    auto library = detail::GlfwLibrary::acquire();
    if (!library) {
        return library.error();
    }
    glfwDefaultWindowHints();
    glfwWindowHint(GLFW_CLIENT_API, GLFW_OPENGL_API);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, kRequiredGlMajor);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, kRequiredGlMinor);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, options.debugContext ? GLFW_TRUE : GLFW_FALSE);
    glfwWindowHint(GLFW_RESIZABLE, options.resizable ? GLFW_TRUE : GLFW_FALSE);
    glfwWindowHint(GLFW_VISIBLE, options.visible ? GLFW_TRUE : GLFW_FALSE);

    const std::string titleText(title);
    GLFWwindow* window = glfwCreateWindow(width, height, titleText.c_str(), nullptr, nullptr);
    if (window == nullptr) {
        const std::string errors = detail::GlfwLibrary::takeErrors();
        return Error{"GLFW: cannot open a " + std::to_string(width) + "x" + std::to_string(height) +
                     " window with OpenGL 4.5 core: " +
                     (errors.empty() ? std::string("no reason given") : errors)};
    }
    glfwMakeContextCurrent(window);
    glfwSwapInterval(options.vsync ? 1 : 0);

    const bool echo = glDebugEchoEnabled(options.echoDebugMessages);
    auto context = std::unique_ptr<GlfwWindowContext>(
        new GlfwWindowContext(std::move(library).value(), window, echo));
    if (!context->m_info.atLeast(kRequiredGlMajor, kRequiredGlMinor) ||
        !context->m_info.coreProfile) {
        return Error{"GLFW: got OpenGL " + context->m_info.version + ", need 4.5 core"};
    }
    return context;
}

GlfwWindowContext::GlfwWindowContext(std::unique_ptr<detail::GlfwLibrary> library,
                                     GLFWwindow* window, bool echoDebugMessages)
    : m_library(std::move(library)), m_window(window) {
    m_info = queryCurrentGlInfo("glfw", std::string("GLFW ") + glfwGetVersionString());
    m_driverWorkarounds = applyDriverWorkarounds(m_info);
    m_debugLog.setEcho(echoDebugMessages);
    m_debugLog.install();
}

GlfwWindowContext::~GlfwWindowContext() {
    GLFWwindow* previous = glfwGetCurrentContext();
    glfwMakeContextCurrent(m_window);
    m_debugLog.uninstall();  // the driver must not call into a destroyed log
    glfwMakeContextCurrent(previous != m_window ? previous : nullptr);
    glfwDestroyWindow(m_window);
    m_library.reset();  // after the window: may terminate GLFW
}

Status GlfwWindowContext::makeCurrent() {
    glfwMakeContextCurrent(m_window);
    if (glfwGetCurrentContext() != m_window) {
        return Error{"GLFW: glfwMakeContextCurrent failed: " + detail::GlfwLibrary::takeErrors()};
    }
    return {};
}

void GlfwWindowContext::swapBuffers() { glfwSwapBuffers(m_window); }

void GlfwWindowContext::setVsync(bool vsync) { glfwSwapInterval(vsync ? 1 : 0); }

bool GlfwWindowContext::shouldClose() const { return glfwWindowShouldClose(m_window) != 0; }

FramebufferSize GlfwWindowContext::framebufferSize() const {
    FramebufferSize size;
    glfwGetFramebufferSize(m_window, &size.width, &size.height);
    return size;
}

}  // namespace terrain::gl
