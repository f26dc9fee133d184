// ViewerOverlay: the Dear ImGui panel over the terrain — live telemetry with rolling plots,
// the camera, and the controls (ε, cache budgets, debug views, freeze LOD, skirts, fog,
// jump to coordinates, paths, logging, screenshots, the key list). It only draws and edits
// ViewerSettings; everything that acts on the session comes back as OverlayRequests.
#pragma once

#include "KeyBindings.h"
#include "TelemetryHistory.h"
#include "ViewerSettings.h"

#include "terrain/gl/GlInfo.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/FrameTelemetry.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace terrain::view {

class ViewControls;

/// What the overlay shows this frame (read-only).
struct OverlayModel {
    std::string_view pyramidName;
    const gl::GlInfo* gl = nullptr;
    int framebufferWidth = 0;
    int framebufferHeight = 0;

    const TelemetryHistory* history = nullptr;
    const runtime::FrameTelemetry* frame = nullptr;  ///< this frame's row so far
    int gpuLayersCapacity = 0;
    double cpuCacheBudgetMiB = 0.0;  ///< the budgets the open session has
    std::uint64_t lodNodes = 0;
    std::size_t glErrors = 0;

    const runtime::Camera* camera = nullptr;
    /// The surface's controls: they draw the camera's lines and the jump section (which may
    /// act on them, e.g. the globe's "whole Earth").
    ViewControls* controls = nullptr;

    bool havePath = false;
    bool playing = false;
    double pathTimeS = 0.0;
    double pathDurationS = 0.0;
    std::string_view pathName;
    bool recording = false;
    std::size_t recordedKeyframes = 0;
    double recordedS = 0.0;
    bool logging = false;
    std::string_view logFile;
    std::uint64_t logRows = 0;

    /// The pyramid's imagery layers (the manifest's, bottom first; at most 4 are drawn).
    std::vector<std::string> imageryNames;

    std::string_view status;  ///< the latest message (a file written, an error)
    bool statusIsError = false;
};

struct OverlayRequests {
    std::vector<ViewerAction> actions;
    bool jump = false;          ///< jump to settings.jumpX/Y at jumpHeightM
    bool applyBudgets = false;  ///< re-open the pyramid with settings.cpuCacheMiB/gpuLayers
};

/// A window of the overlay, in framebuffer pixels (for tests: where the overlay is).
struct OverlayWindowRect {
    std::string name;
    float x = 0.0f;
    float y = 0.0f;
    float width = 0.0f;
    float height = 0.0f;
};

/// Between ImGuiLayer::newFrame() and render(). Render thread only.
class ViewerOverlay {
public:
    /// Draws the panel when settings.overlayVisible; returns what the user asked for.
    OverlayRequests draw(const OverlayModel& model, ViewerSettings& settings);

    /// Opens the camera section with the cursor in the jump-to fields (key J).
    void focusJump() { m_focusJump = true; }

    /// The windows drawn by the last draw() (empty when hidden).
    const std::vector<OverlayWindowRect>& windows() const { return m_windows; }

private:
    void drawTelemetry(const OverlayModel& model);
    void drawCamera(const OverlayModel& model, ViewerSettings& settings, OverlayRequests& out);
    void drawView(ViewerSettings& settings, OverlayRequests& out);
    void drawImagery(const OverlayModel& model, ViewerSettings& settings);
    void drawCaches(const OverlayModel& model, ViewerSettings& settings, OverlayRequests& out);
    void drawPathAndOutput(const OverlayModel& model, OverlayRequests& out);
    void drawKeys();

    std::vector<OverlayWindowRect> m_windows;
    bool m_focusJump = false;
};

}  // namespace terrain::view
