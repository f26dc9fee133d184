// GLFW callbacks → Dear ImGui first, then the camera and the key actions.
#include "WindowInput.h"

#include <backends/imgui_impl_glfw.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <utility>

namespace terrain::view {
namespace {

bool held(GLFWwindow* window, int key) { return glfwGetKey(window, key) == GLFW_PRESS; }

}  // namespace

WindowInput::WindowInput(GLFWwindow* window, ImGuiLayer& overlay)
    : m_window(window), m_overlay(overlay) {
    m_actions.reserve(16);
    glfwSetWindowUserPointer(window, this);
    glfwSetKeyCallback(window, &onKey);
    glfwSetCharCallback(window, &onChar);
    glfwSetMouseButtonCallback(window, &onMouseButton);
    glfwSetCursorPosCallback(window, &onCursorPos);
    glfwSetScrollCallback(window, &onScroll);
    glfwSetWindowFocusCallback(window, &onFocus);
    glfwSetCursorEnterCallback(window, &onCursorEnter);
}

WindowInput::~WindowInput() {
    endDrag();
    glfwSetKeyCallback(m_window, nullptr);
    glfwSetCharCallback(m_window, nullptr);
    glfwSetMouseButtonCallback(m_window, nullptr);
    glfwSetCursorPosCallback(m_window, nullptr);
    glfwSetScrollCallback(m_window, nullptr);
    glfwSetWindowFocusCallback(m_window, nullptr);
    glfwSetCursorEnterCallback(m_window, nullptr);
    glfwSetWindowUserPointer(m_window, nullptr);
}

WindowInput* WindowInput::from(GLFWwindow* window) {
    return static_cast<WindowInput*>(glfwGetWindowUserPointer(window));
}

runtime::CameraInput WindowInput::takeCameraInput() {
    runtime::CameraInput input;
    if (!m_overlay.wantsKeyboard()) {
        GLFWwindow* w = m_window;
        input.forward = held(w, GLFW_KEY_W) || held(w, GLFW_KEY_UP);
        input.back = held(w, GLFW_KEY_S) || held(w, GLFW_KEY_DOWN);
        input.left = held(w, GLFW_KEY_A) || held(w, GLFW_KEY_LEFT);
        input.right = held(w, GLFW_KEY_D) || held(w, GLFW_KEY_RIGHT);
        input.down = held(w, GLFW_KEY_Q) || held(w, GLFW_KEY_PAGE_DOWN);
        input.up = held(w, GLFW_KEY_E) || held(w, GLFW_KEY_PAGE_UP);
        input.boost = held(w, GLFW_KEY_LEFT_SHIFT) || held(w, GLFW_KEY_RIGHT_SHIFT);
        input.slow = held(w, GLFW_KEY_LEFT_CONTROL) || held(w, GLFW_KEY_RIGHT_CONTROL);
    }
    input.lookDxPx = std::exchange(m_dragDx, 0.0);
    input.lookDyPx = std::exchange(m_dragDy, 0.0);
    input.wheelSteps = std::exchange(m_wheel, 0.0);
    return input;
}

std::vector<ViewerAction> WindowInput::takeActions() {
    std::vector<ViewerAction> actions;
    actions.swap(m_actions);
    m_actions.reserve(16);
    return actions;
}

std::optional<PixelPosition> WindowInput::takeOrbitClick() {
    return std::exchange(m_orbitClick, {});
}

void WindowInput::onKey(GLFWwindow* window, int key, int scancode, int action, int mods) {
    ImGui_ImplGlfw_KeyCallback(window, key, scancode, action, mods);
    WindowInput* self = from(window);
    if (self == nullptr || action != GLFW_PRESS || self->m_overlay.wantsKeyboard()) return;
    if (const auto bound = actionForKey(key)) self->m_actions.push_back(*bound);
}

void WindowInput::onChar(GLFWwindow* window, unsigned int codepoint) {
    ImGui_ImplGlfw_CharCallback(window, codepoint);
}

void WindowInput::onMouseButton(GLFWwindow* window, int button, int action, int mods) {
    WindowInput* self = from(window);
    if (self == nullptr) {
        ImGui_ImplGlfw_MouseButtonCallback(window, button, action, mods);
        return;
    }
    if (action == GLFW_RELEASE && button == self->m_dragButton) {
        self->endDrag();
        return;
    }
    if (self->dragging()) return;  // a second button during a drag: the drag keeps it
    const bool overlay = self->m_overlay.wantsMouse();
    if (overlay || action != GLFW_PRESS) {
        ImGui_ImplGlfw_MouseButtonCallback(window, button, action, mods);
        return;
    }
    if (button == GLFW_MOUSE_BUTTON_LEFT || button == GLFW_MOUSE_BUTTON_RIGHT) {
        self->startDrag(button);
    } else if (button == GLFW_MOUSE_BUTTON_MIDDLE) {
        self->m_orbitClick = self->cursorInFramebufferPixels();
    }
}

void WindowInput::onCursorPos(GLFWwindow* window, double x, double y) {
    WindowInput* self = from(window);
    if (self == nullptr || !self->dragging()) return;
    self->m_dragDx += x - self->m_lastX;
    self->m_dragDy += y - self->m_lastY;
    self->m_lastX = x;
    self->m_lastY = y;
}

void WindowInput::onScroll(GLFWwindow* window, double dx, double dy) {
    ImGui_ImplGlfw_ScrollCallback(window, dx, dy);
    WindowInput* self = from(window);
    if (self == nullptr || self->m_overlay.wantsMouse()) return;
    self->m_wheel += dy;
}

void WindowInput::onFocus(GLFWwindow* window, int focused) {
    ImGui_ImplGlfw_WindowFocusCallback(window, focused);
    WindowInput* self = from(window);
    if (self != nullptr && focused == GLFW_FALSE) self->endDrag();
}

void WindowInput::onCursorEnter(GLFWwindow* window, int entered) {
    ImGui_ImplGlfw_CursorEnterCallback(window, entered);
}

void WindowInput::startDrag(int button) {
    m_dragButton = button;
    glfwGetCursorPos(m_window, &m_lastX, &m_lastY);
    // A hidden, unbounded cursor: the drag can turn the camera round any number of times.
    glfwSetInputMode(m_window, GLFW_CURSOR, GLFW_CURSOR_DISABLED);
    glfwGetCursorPos(m_window, &m_lastX, &m_lastY);
    m_overlay.setMouseIgnored(true);
}

void WindowInput::endDrag() {
    if (m_dragButton < 0) return;
    m_dragButton = -1;
    glfwSetInputMode(m_window, GLFW_CURSOR, GLFW_CURSOR_NORMAL);
    m_overlay.setMouseIgnored(false);
}

PixelPosition WindowInput::cursorInFramebufferPixels() const {
    double x = 0.0, y = 0.0;
    glfwGetCursorPos(m_window, &x, &y);
    int windowW = 0, windowH = 0, framebufferW = 0, framebufferH = 0;
    glfwGetWindowSize(m_window, &windowW, &windowH);
    glfwGetFramebufferSize(m_window, &framebufferW, &framebufferH);
    const double sx = windowW > 0 ? static_cast<double>(framebufferW) / windowW : 1.0;
    const double sy = windowH > 0 ? static_cast<double>(framebufferH) / windowH : 1.0;
    return {x * sx, y * sy};
}

}  // namespace terrain::view
