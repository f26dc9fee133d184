// ImGuiLayer: the Dear ImGui context and its GLFW and OpenGL 3 backends, owned as one RAII
// object: created after the window, shut down (backends, then the context) before it.
// Events reach ImGui through WindowInput, which decides what the overlay and the camera get.
#pragma once

#include "terrain/base/Result.h"

#include <memory>

struct GLFWwindow;
struct ImGuiContext;

namespace terrain::view {

/// Main thread only (GLFW), with the window's GL context current.
class ImGuiLayer {
public:
    static Result<std::unique_ptr<ImGuiLayer>> create(GLFWwindow* window);
    ~ImGuiLayer();
    ImGuiLayer(const ImGuiLayer&) = delete;
    ImGuiLayer& operator=(const ImGuiLayer&) = delete;

    /// Starts an overlay frame (after the events are polled).
    void newFrame();
    /// Draws the frame's overlay into the window's framebuffer (bound by the caller). The
    /// OpenGL 3 backend saves and restores the GL state it touches.
    void render();

    /// Whether the overlay uses the mouse or keyboard now (hovered, a text field active), so
    /// the camera must not.
    bool wantsMouse() const;
    bool wantsKeyboard() const;
    /// Ignore the mouse entirely (while the camera is being dragged).
    void setMouseIgnored(bool ignored);

private:
    explicit ImGuiLayer(ImGuiContext* context) : m_context(context) {}

    ImGuiContext* m_context = nullptr;
    bool m_glfwBackend = false;
    bool m_glBackend = false;
};

}  // namespace terrain::view
