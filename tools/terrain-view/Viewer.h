// Viewer: terrain-view's window, session and frame loop, the same for a planar and a globe
// pyramid (what differs, the camera controls and what the overlay says about the camera, is
// the surface's ViewControls). Each frame: poll events, turn them into actions and camera
// motion (or play the path), run the TerrainSession frame protocol into the offscreen scene,
// copy it to the window, draw the overlay on top, write what was asked for (screenshot,
// telemetry row, path keyframe), present.
#pragma once

#include "FaultPrinter.h"
#include "ImGuiLayer.h"
#include "OutputNames.h"
#include "PathRecorder.h"
#include "SceneTarget.h"
#include "TelemetryHistory.h"
#include "ViewControls.h"
#include "ViewerOptions.h"
#include "ViewerOverlay.h"
#include "SurfaceKit.h"
#include "ViewerSettings.h"
#include "WindowInput.h"

#include "terrain/base/Result.h"
#include "terrain/gl/GlfwWindowContext.h"
#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/FlightPath.h"
#include "terrain/runtime/TelemetryCsvWriter.h"
#include "terrain/runtime/TelemetrySummary.h"
#include "terrain/runtime/TerrainSession.h"

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace terrain::view {

/// Main thread only (GLFW and the GL context live there).
class Viewer {
public:
    /// Checks the pyramid, the path file and the output folders before opening the window,
    /// then opens the window (OpenGL 4.5 core), the session and the overlay. Errors name
    /// the file or say what the system lacks.
    static Result<std::unique_ptr<Viewer>> create(const ViewerOptions& options);
    ~Viewer();
    Viewer(const Viewer&) = delete;
    Viewer& operator=(const Viewer&) = delete;

    /// Runs until the window closes, Esc, --frames or --exit-after; writes the exit files
    /// and the --json summary. Returns the exit status (1 when an exit file could not be
    /// written or OpenGL reported an error).
    int run();

private:
    using Clock = std::chrono::steady_clock;

    Viewer(const ViewerOptions& options, std::unique_ptr<tools::SurfaceKit> kit);
    Status openSession(double cpuCacheMiB, int gpuLayers);
    void reopenSession();
    void initialCamera();

    void handle(ViewerAction action);
    void applySettings();
    void moveCamera(const runtime::CameraInput& input, double dtS);
    void orbitAt(double xPx, double yPx, bool fallbackAhead);
    void jump();
    void toggleRecording();
    Status startTelemetryLog();
    void toggleTelemetryLog();
    void takeScreenshot(const std::filesystem::path& path);
    void checkGlErrors();
    void setStatus(std::string message, bool error = false);
    /// New streaming faults to stderr; a root that cannot be read on screen, once.
    void reportFaults();
    OverlayModel overlayModel(const runtime::FrameTelemetry& frame) const;
    bool finishExitFiles();
    void printSummary(double wallS) const;

    ViewerOptions m_options;
    std::string m_pyramidName;
    std::unique_ptr<tools::SurfaceKit> m_kit;  // the sky, the fog, the root fault, the paths
    std::optional<runtime::FlightPath> m_path;

    // Destroyed in reverse: the session's GL objects and the overlay before the window.
    std::unique_ptr<gl::GlfwWindowContext> m_window;
    std::unique_ptr<ImGuiLayer> m_imgui;
    std::unique_ptr<WindowInput> m_input;
    std::unique_ptr<runtime::TerrainSession> m_session;
    std::unique_ptr<ViewControls> m_controls;  // follows m_session (reads its streamer)
    SceneTarget m_scene;
    ViewerOverlay m_overlay;

    ViewerSettings m_settings;
    ViewerSettings m_applied;  // what the session, style and window have now
    double m_appliedCpuCacheMiB = 0.0;
    int m_appliedGpuLayers = 0;
    runtime::TerrainStyle m_style;
    runtime::Camera m_camera;

    bool m_playing = false;
    double m_pathTimeS = 0.0;
    PathRecorder m_recorder;
    std::filesystem::path m_recordingFile;
    OutputNames m_recordNames;
    OutputNames m_screenshotNames;
    OutputNames m_telemetryNames;
    std::optional<runtime::TelemetryCsvWriter> m_csv;
    std::string m_logFileText;  // m_csv's file, for the overlay

    TelemetryHistory m_history;
    runtime::TelemetrySummary m_summary;
    std::uint64_t m_frame = 0;
    double m_timeS = 0.0;  // flight time: wall clock, or frames / --fps
    bool m_quit = false;
    bool m_screenshotRequested = false;
    std::size_t m_glErrorsReported = 0;
    std::string m_status;
    bool m_statusIsError = false;
    bool m_exitFilesFailed = false;
    tools::FaultPrinter m_faultPrinter{"terrain-view"};
    bool m_fatalFaultShown = false;  // the root failed: said once, exit status 1

    std::vector<std::string> m_screenshotsWritten;
    std::vector<std::string> m_telemetryWritten;
    std::vector<std::string> m_pathsRecorded;
};

}  // namespace terrain::view
