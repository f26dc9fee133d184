// GlobeViewer: terrain-view on a globe pyramid (DESIGN.md, "The globe"): the window, the
// TerrainSession frame protocol and the globe controls a user of a virtual globe expects (drag
// to spin the globe, the wheel zooming toward the cursor, Shift-drag to look around, WASD and
// Q/E flight whose speed follows the height, "go to the data", "the whole Earth", fly to a
// latitude and longitude), under a small overlay of where the camera is and what is drawn.
#pragma once

#include "FaultPrinter.h"
#include "ImGuiLayer.h"
#include "SceneTarget.h"
#include "ViewerOptions.h"
#include "WindowInput.h"

#include "terrain/base/Result.h"
#include "terrain/gl/GlfwWindowContext.h"
#include "terrain/runtime/GlobeController.h"
#include "terrain/runtime/TerrainSession.h"

#include <memory>
#include <optional>
#include <string>

namespace terrain::view {

/// Main thread only.
class GlobeViewer {
public:
    /// Opens the window, the session and the overlay for a globe pyramid; errors name the
    /// pyramid or say what the system lacks.
    static Result<std::unique_ptr<GlobeViewer>> create(const ViewerOptions& options);
    ~GlobeViewer();
    GlobeViewer(const GlobeViewer&) = delete;
    GlobeViewer& operator=(const GlobeViewer&) = delete;

    /// Runs until the window closes, Esc, --frames or --exit-after; writes --screenshot and
    /// the --json summary. Returns the exit status.
    int run();

private:
    explicit GlobeViewer(const ViewerOptions& options) : m_options(options) {}
    std::optional<globe::Geodetic> groundUnderPixel(double xPx, double yPx) const;
    double floorUnderCamera() const;
    void drawOverlay(const runtime::FrameTelemetry& t);

    ViewerOptions m_options;
    std::unique_ptr<gl::GlfwWindowContext> m_window;
    std::unique_ptr<runtime::TerrainSession> m_session;
    std::unique_ptr<ImGuiLayer> m_imgui;
    std::unique_ptr<WindowInput> m_input;
    SceneTarget m_scene;
    runtime::Camera m_camera;
    runtime::GlobePose m_pose;
    runtime::GlobeController m_controller;
    runtime::TerrainStyle m_style;
    bool m_overlayVisible = true;
    bool m_quit = false;
    std::array<double, 3> m_flyTo{0.0, 0.0, 10000.0};  // the overlay's fields
    std::string m_status;
    tools::FaultPrinter m_faultPrinter{"terrain-view"};
};

}  // namespace terrain::view
