// The overlay panel, immediate mode: one window, telemetry on top, controls in sections.
#include "ViewerOverlay.h"

#include "OverlayWidgets.h"
#include "ViewControls.h"

#include <fmt/core.h>
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace terrain::view {
namespace {

using overlay::button;
using overlay::dimText;
using overlay::kDim;
using overlay::kGood;
using overlay::kWarn;
using overlay::text;

constexpr float kPanelWidth = 360.0f;
constexpr float kLabelWidth = 72.0f;
constexpr float kPlotHeight = 38.0f;
std::string count(double value) {
    if (value >= 1e9) return fmt::format("{:.2f} G", value / 1e9);
    if (value >= 1e6) return fmt::format("{:.2f} M", value / 1e6);
    if (value >= 1e4) return fmt::format("{:.1f} k", value / 1e3);
    return fmt::format("{:.0f}", value);
}

std::string mib(double bytes) { return fmt::format("{:.0f}", bytes / (1024.0 * 1024.0)); }

std::string optionalMs(double ms) { return std::isnan(ms) ? "-" : fmt::format("{:.1f}", ms); }

// A label in the dimmed colour and its value in the next table column.
void row(const char* label, const std::string& value) {
    ImGui::TableNextColumn();
    ImGui::PushStyleColor(ImGuiCol_Text, kDim);
    ImGui::TextUnformatted(label);
    ImGui::PopStyleColor();
    ImGui::TableNextColumn();
    ImGui::TextUnformatted(value.c_str());
}

}  // namespace

OverlayRequests ViewerOverlay::draw(const OverlayModel& model, ViewerSettings& settings) {
    OverlayRequests out;
    m_windows.clear();
    if (!settings.overlayVisible) return out;

    ImGui::SetNextWindowPos(ImVec2(8.0f, 8.0f), ImGuiCond_Always);
    ImGui::SetNextWindowSizeConstraints(ImVec2(kPanelWidth, 0.0f), ImVec2(kPanelWidth, 1e6f));
    const ImGuiWindowFlags flags = ImGuiWindowFlags_AlwaysAutoResize |
                                   ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoMove |
                                   ImGuiWindowFlags_NoCollapse;
    if (ImGui::Begin("terrain-view", nullptr, flags)) {
        drawTelemetry(model);
        drawView(settings, out);
        drawImagery(model, settings);
        drawCamera(model, settings, out);
        drawCaches(model, settings, out);
        drawPathAndOutput(model, out);
        drawKeys();
        if (!model.status.empty()) {
            ImGui::Separator();
            ImGui::PushStyleColor(ImGuiCol_Text, model.statusIsError ? kWarn : kGood);
            ImGui::PushTextWrapPos(0.0f);
            ImGui::TextUnformatted(model.status.data(), model.status.data() + model.status.size());
            ImGui::PopTextWrapPos();
            ImGui::PopStyleColor();
        }
    }
    const ImVec2 pos = ImGui::GetWindowPos();
    const ImVec2 size = ImGui::GetWindowSize();
    m_windows.push_back({"terrain-view", pos.x, pos.y, size.x, size.y});
    ImGui::End();
    return out;
}

void ViewerOverlay::drawTelemetry(const OverlayModel& model) {
    const TelemetryHistory& history = *model.history;
    const runtime::FrameTelemetry& t = *model.frame;
    std::string renderer = model.gl != nullptr ? model.gl->renderer : "";
    renderer = renderer.substr(0, renderer.find(" ("));  // "llvmpipe (LLVM 15.0.6, 256 bits)"
    dimText(fmt::format("{} · {}×{} · {}", model.pyramidName, model.framebufferWidth,
                        model.framebufferHeight, renderer));

    if (ImGui::BeginTable("telemetry", 4, ImGuiTableFlags_SizingFixedFit)) {
        ImGui::TableSetupColumn("label", ImGuiTableColumnFlags_WidthFixed, kLabelWidth);
        ImGui::TableSetupColumn("value", ImGuiTableColumnFlags_WidthStretch);
        ImGui::TableSetupColumn("label2", ImGuiTableColumnFlags_WidthFixed, kLabelWidth);
        ImGui::TableSetupColumn("value2", ImGuiTableColumnFlags_WidthStretch);
        const auto fps = history.framesPerSecond();
        const auto frameMs = history.meanFrameMs();
        row("fps", fps ? fmt::format("{:.1f}", *fps) : "-");
        row("frame", frameMs ? fmt::format("{:.2f} ms", *frameMs) : "-");
        row("LOD", std::isnan(t.lodUpdateUs) ? "frozen" : fmt::format("{:.0f} µs", t.lodUpdateUs));
        const auto gpuMs = history.latestGpuMs();
        row("GPU", gpuMs ? fmt::format("{:.2f} ms", *gpuMs) : "-");
        const auto triangles = history.latestTriangles();
        row("triangles", triangles ? count(static_cast<double>(*triangles)) : "-");
        row("draw calls", fmt::format("{}", t.drawCalls));
        row("patches", fmt::format("{}", t.patchesDrawn));
        row("culled", fmt::format("{}", t.patchesCulled));
        row("resident", fmt::format("{} / {}", t.gpuLayersUsed, model.gpuLayersCapacity));
        row("CPU cache", fmt::format("{} / {} MiB", mib(static_cast<double>(t.cpuCacheBytes)),
                                     mib(static_cast<double>(t.cpuCacheBudgetBytes))));
        row("queue", fmt::format("{} (+{} I/O)", t.queueDepth, t.ioInFlight));
        const auto hitRate = history.cacheHitRate();
        row("hit rate", hitRate ? fmt::format("{:.0f} %", *hitRate * 100.0) : "-");
        row("load p50", optionalMs(t.loadLatencyP50Ms) + " ms");
        row("load p95", optionalMs(t.loadLatencyP95Ms) + " ms");
        row("faults", fmt::format("{}", t.faultsTotal));
        row("GL errors", fmt::format("{}", model.glErrors));
        ImGui::EndTable();
    }

    if (history.seriesCount() > 1) {
        const float width = ImGui::GetContentRegionAvail().x;
        float maxMs = 0.0f, maxUs = 0.0f;
        for (int i = 0; i < history.seriesCount(); ++i) {
            maxMs = std::max(maxMs, history.frameMsSeries()[i]);
            maxUs = std::max(maxUs, history.lodUsSeries()[i]);
        }
        const std::string frameLabel = fmt::format("frame ms (max {:.1f})", maxMs);
        ImGui::PlotLines("##frame_ms", history.frameMsSeries(), history.seriesCount(),
                         history.seriesOffset(), frameLabel.c_str(), 0.0f,
                         std::max(maxMs * 1.1f, 1.0f), ImVec2(width, kPlotHeight));
        const std::string lodLabel = fmt::format("LOD µs (max {:.0f})", maxUs);
        ImGui::PlotLines("##lod_us", history.lodUsSeries(), history.seriesCount(),
                         history.seriesOffset(), lodLabel.c_str(), 0.0f,
                         std::max(maxUs * 1.1f, 1.0f), ImVec2(width, kPlotHeight));
    }

    model.controls->drawCameraLines(*model.camera, model.playing);
}

void ViewerOverlay::drawView(ViewerSettings& settings, OverlayRequests&) {
    if (!ImGui::CollapsingHeader("View", ImGuiTreeNodeFlags_DefaultOpen)) return;
    float errorPx = static_cast<float>(settings.errorPx);
    ImGui::SetNextItemWidth(-80.0f);
    if (ImGui::SliderFloat("error px", &errorPx, static_cast<float>(ViewerSettings::kMinErrorPx),
                           static_cast<float>(ViewerSettings::kMaxErrorPx), "%.2f",
                           ImGuiSliderFlags_Logarithmic)) {
        settings.errorPx = errorPx;
    }
    int view = static_cast<int>(settings.debugView);
    ImGui::RadioButton("shaded", &view, static_cast<int>(runtime::TerrainDebugView::Shaded));
    ImGui::SameLine();
    ImGui::RadioButton("by level", &view, static_cast<int>(runtime::TerrainDebugView::Level));
    ImGui::SameLine();
    ImGui::RadioButton("by tess factor", &view,
                       static_cast<int>(runtime::TerrainDebugView::TessFactor));
    settings.debugView = static_cast<runtime::TerrainDebugView>(view);

    ImGui::Checkbox("wireframe", &settings.wireframe);
    ImGui::SameLine();
    ImGui::Checkbox("skirts", &settings.skirts);
    ImGui::SameLine();
    ImGui::Checkbox("fog", &settings.fog);
    ImGui::SameLine();
    ImGui::Checkbox("vsync", &settings.vsync);
    ImGui::Checkbox("freeze LOD", &settings.lodFrozen);
    if (ImGui::IsItemHovered()) {
        ImGui::SetTooltip(
            "Keeps the current patches and culling; fly away to see the cut from outside.");
    }
    ImGui::SameLine();
    ImGui::Checkbox("keep above ground", &settings.keepAboveGround);
    if (settings.fog) {
        float density = settings.fogDensityPerM * 1e4f;
        ImGui::SetNextItemWidth(-120.0f);
        if (ImGui::SliderFloat("fog per 10 km", &density, 0.01f, 100.0f, "%.2f",
                               ImGuiSliderFlags_Logarithmic)) {
            settings.fogDensityPerM = density * 1e-4f;
        }
    }
    ImGui::SetNextItemWidth(-160.0f);
    ImGui::SliderInt("measure every N frames", &settings.measureEvery, 1, 120);
    if (ImGui::IsItemHovered()) {
        ImGui::SetTooltip(
            "Triangles and GPU time need the CPU to wait for the GPU; "
            "measuring every frame costs frame rate.");
    }
}

// The imagery layers, top first as a layer list reads: each shown or not, its opacity, and
// buttons that move it up or down the composite.
void ViewerOverlay::drawImagery(const OverlayModel& model, ViewerSettings& settings) {
    const int layers = std::min<int>(static_cast<int>(model.imageryNames.size()), 4);
    if (layers == 0 || !ImGui::CollapsingHeader("Imagery", ImGuiTreeNodeFlags_DefaultOpen)) return;
    ImGui::Checkbox("imagery", &settings.imagery);
    ImGui::SameLine();
    ImGui::Checkbox("lit by the sun", &settings.imageryLit);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("Off: drawn as it is (imagery often has its shadows baked in).");
    for (int drawn = layers - 1; drawn >= 0; --drawn) {
        const auto d = static_cast<std::size_t>(drawn);
        const int layer = settings.imageryOrder[d];
        const auto l = static_cast<std::size_t>(layer);
        ImGui::PushID(layer);
        ImGui::Checkbox("##shown", &settings.imageryShown[l]);
        ImGui::SameLine();
        ImGui::BeginDisabled(drawn == layers - 1);
        if (ImGui::ArrowButton("##up", ImGuiDir_Up))
            std::swap(settings.imageryOrder[d], settings.imageryOrder[d + 1]);
        ImGui::EndDisabled();
        ImGui::SameLine();
        ImGui::BeginDisabled(drawn == 0);
        if (ImGui::ArrowButton("##down", ImGuiDir_Down))
            std::swap(settings.imageryOrder[d], settings.imageryOrder[d - 1]);
        ImGui::EndDisabled();
        ImGui::SameLine();
        ImGui::SetNextItemWidth(-150.0f);
        ImGui::SliderFloat("##opacity", &settings.imageryOpacity[l], 0.0f, 1.0f, "%.2f");
        ImGui::SameLine();
        ImGui::TextUnformatted(model.imageryNames[l].c_str());
        ImGui::PopID();
    }
}

void ViewerOverlay::drawCamera(const OverlayModel& model, ViewerSettings& settings,
                               OverlayRequests& out) {
    const ImGuiTreeNodeFlags open = m_focusJump ? ImGuiTreeNodeFlags_DefaultOpen : 0;
    if (m_focusJump) ImGui::SetNextItemOpen(true);
    if (!ImGui::CollapsingHeader("Camera and jump to", open)) {
        m_focusJump = false;
        return;
    }
    model.controls->drawCameraSection(*model.camera, settings, out, m_focusJump);
    m_focusJump = false;
}

void ViewerOverlay::drawCaches(const OverlayModel& model, ViewerSettings& settings,
                               OverlayRequests& out) {
    if (!ImGui::CollapsingHeader("Cache budgets")) return;
    dimText(fmt::format("open with: CPU {:.0f} MiB, GPU {} layers · {} LOD nodes",
                        model.cpuCacheBudgetMiB, model.gpuLayersCapacity, model.lodNodes));
    ImGui::SetNextItemWidth(-120.0f);
    ImGui::InputDouble("CPU cache MiB", &settings.cpuCacheMiB, 16.0, 256.0, "%.0f");
    settings.cpuCacheMiB = std::clamp(settings.cpuCacheMiB, 1.0, 1024.0 * 1024.0);
    ImGui::SetNextItemWidth(-120.0f);
    ImGui::InputInt("GPU layers", &settings.gpuLayers, 16, 256);
    settings.gpuLayers = std::clamp(settings.gpuLayers, 1, 1 << 16);
    const bool changed = settings.cpuCacheMiB != model.cpuCacheBudgetMiB ||
                         settings.gpuLayers != model.gpuLayersCapacity;
    if (!changed) ImGui::BeginDisabled();
    if (button("apply (re-opens the pyramid)")) out.applyBudgets = true;
    if (!changed) ImGui::EndDisabled();
    dimText(
        "Budgets are fixed while a pyramid is open: applying\nre-opens it, and tiles stream in "
        "again.");
}

void ViewerOverlay::drawPathAndOutput(const OverlayModel& model, OverlayRequests& out) {
    if (!ImGui::CollapsingHeader("Path, recording, output")) return;
    if (model.havePath) {
        text(fmt::format("path {} · {:.1f} / {:.1f} s{}", model.pathName, model.pathTimeS,
                         model.pathDurationS, model.playing ? " · playing" : ""));
        if (button(model.playing ? "pause (Space)" : "play (Space)")) {
            out.actions.push_back(ViewerAction::PlayPause);
        }
        ImGui::SameLine();
        if (button("restart (Backspace)")) out.actions.push_back(ViewerAction::RestartPath);
    } else {
        dimText("no path: --path FILE plays one, R records one");
    }
    if (model.recording) {
        ImGui::TextColored(kWarn, "recording: %zu keyframes, %.1f s", model.recordedKeyframes,
                           model.recordedS);
    }
    if (button(model.recording ? "stop recording (R)" : "record path (R)")) {
        out.actions.push_back(ViewerAction::ToggleRecording);
    }
    if (model.logging) {
        ImGui::TextColored(kWarn, "logging telemetry: %llu rows",
                           static_cast<unsigned long long>(model.logRows));
        dimText(std::string(model.logFile));
    }
    if (button(model.logging ? "stop telemetry log (T)" : "log telemetry CSV (T)")) {
        out.actions.push_back(ViewerAction::ToggleTelemetryLog);
    }
    ImGui::SameLine();
    if (button("screenshot (P)")) out.actions.push_back(ViewerAction::Screenshot);
}

void ViewerOverlay::drawKeys() {
    if (!ImGui::CollapsingHeader("Keys")) return;
    if (ImGui::BeginTable("keys", 2, ImGuiTableFlags_SizingFixedFit)) {
        for (const HeldControl& control : heldControls()) {
            ImGui::TableNextColumn();
            ImGui::TextColored(kDim, "%.*s", static_cast<int>(control.keys.size()),
                               control.keys.data());
            ImGui::TableNextColumn();
            ImGui::TextUnformatted(control.description.data(),
                                   control.description.data() + control.description.size());
        }
        for (const KeyBinding& binding : keyBindings()) {
            ImGui::TableNextColumn();
            ImGui::TextColored(kDim, "%.*s", static_cast<int>(binding.keys.size()),
                               binding.keys.data());
            ImGui::TableNextColumn();
            ImGui::TextUnformatted(binding.description.data(),
                                   binding.description.data() + binding.description.size());
        }
        ImGui::EndTable();
    }
}

}  // namespace terrain::view
