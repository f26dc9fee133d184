// WindowInput: GLFW's events split between the overlay and the camera. Every event goes to
// Dear ImGui first; what the overlay does not want becomes camera input (held keys, mouse
// drags, the wheel), key actions (KeyBindings.h) or a point to orbit (middle click). This is
// the only GLFW-specific input code: the camera controller itself takes a CameraInput.
#pragma once

#include "ImGuiLayer.h"
#include "KeyBindings.h"

#include "terrain/runtime/CameraController.h"

#include <optional>
#include <vector>

struct GLFWwindow;

namespace terrain::view {

/// A window pixel (framebuffer pixels, origin top-left).
struct PixelPosition {
    double x = 0.0;
    double y = 0.0;
};

/// Installs its callbacks on the window for its lifetime. Main thread only (GLFW).
class WindowInput {
public:
    WindowInput(GLFWwindow* window, ImGuiLayer& overlay);
    ~WindowInput();
    WindowInput(const WindowInput&) = delete;
    WindowInput& operator=(const WindowInput&) = delete;

    /// The camera input since the previous call: held keys as they are now (none while the
    /// overlay has the keyboard), mouse travel while dragging and wheel steps.
    runtime::CameraInput takeCameraInput();
    /// Key actions pressed since the previous call, in order.
    std::vector<ViewerAction> takeActions();
    /// The pixel middle-clicked since the previous call, if any.
    std::optional<PixelPosition> takeOrbitClick();

    bool dragging() const { return m_dragButton >= 0; }
    /// Where the cursor is, in framebuffer pixels (rows top-down).
    PixelPosition cursorInFramebufferPixels() const;

private:
    static WindowInput* from(GLFWwindow* window);
    static void onKey(GLFWwindow* window, int key, int scancode, int action, int mods);
    static void onChar(GLFWwindow* window, unsigned int codepoint);
    static void onMouseButton(GLFWwindow* window, int button, int action, int mods);
    static void onCursorPos(GLFWwindow* window, double x, double y);
    static void onScroll(GLFWwindow* window, double dx, double dy);
    static void onFocus(GLFWwindow* window, int focused);
    static void onCursorEnter(GLFWwindow* window, int entered);

    void startDrag(int button);
    void endDrag();

    GLFWwindow* m_window;
    ImGuiLayer& m_overlay;
    std::vector<ViewerAction> m_actions;
    std::optional<PixelPosition> m_orbitClick;
    int m_dragButton = -1;  // the GLFW mouse button dragging the camera, or -1
    double m_lastX = 0.0;
    double m_lastY = 0.0;
    double m_dragDx = 0.0;
    double m_dragDy = 0.0;
    double m_wheel = 0.0;
};

}  // namespace terrain::view
