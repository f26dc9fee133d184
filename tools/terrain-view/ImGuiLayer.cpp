// Dear ImGui context and backends.
#include "ImGuiLayer.h"

#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

namespace terrain::view {
namespace {

// The backend's shader variant with layout(location) qualifiers; any 4.x core context has it.
constexpr const char* kGlslVersion = "#version 410 core";

void applyStyle() {
    ImGui::StyleColorsDark();
    ImGuiStyle& style = ImGui::GetStyle();
    style.WindowRounding = 4.0f;
    style.FrameRounding = 2.0f;
    style.WindowPadding = ImVec2(8.0f, 6.0f);
    style.ItemSpacing = ImVec2(6.0f, 3.0f);
    // Opaque enough to read over bright terrain, transparent enough to see what is behind.
    style.Colors[ImGuiCol_WindowBg] = ImVec4(0.05f, 0.06f, 0.08f, 0.82f);
}

}  // namespace

Result<std::unique_ptr<ImGuiLayer>> ImGuiLayer::create(GLFWwindow* window) {
    IMGUI_CHECKVERSION();
    ImGuiContext* context = ImGui::CreateContext();
    std::unique_ptr<ImGuiLayer> layer(new ImGuiLayer(context));
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;  // no imgui.ini in the user's working folder
    io.LogFilename = nullptr;
    applyStyle();
    // Events are forwarded by WindowInput: it shares them between the overlay and the camera.
    layer->m_glfwBackend = ImGui_ImplGlfw_InitForOpenGL(window, false);
    if (!layer->m_glfwBackend) return Error{"Dear ImGui: the GLFW backend did not start"};
    layer->m_glBackend = ImGui_ImplOpenGL3_Init(kGlslVersion);
    if (!layer->m_glBackend) return Error{"Dear ImGui: the OpenGL 3 backend did not start"};
    return layer;
}

ImGuiLayer::~ImGuiLayer() {
    ImGui::SetCurrentContext(m_context);
    if (m_glBackend) ImGui_ImplOpenGL3_Shutdown();
    if (m_glfwBackend) ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext(m_context);
}

void ImGuiLayer::newFrame() {
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
}

void ImGuiLayer::render() {
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

bool ImGuiLayer::wantsMouse() const { return ImGui::GetIO().WantCaptureMouse; }

bool ImGuiLayer::wantsKeyboard() const { return ImGui::GetIO().WantCaptureKeyboard; }

void ImGuiLayer::setMouseIgnored(bool ignored) {
    ImGuiIO& io = ImGui::GetIO();
    if (ignored) {
        io.ConfigFlags |= ImGuiConfigFlags_NoMouse;
    } else {
        io.ConfigFlags &= ~ImGuiConfigFlags_NoMouse;
    }
}

}  // namespace terrain::view
