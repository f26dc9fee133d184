// terrain-view's frame loop and the actions of its keys and overlay.
#include "Viewer.h"

#include "GlInfoJson.h"
#include "Screenshot.h"

#include "terrain/runtime/LodMethod.h"
#include "terrain/runtime/Surface.h"

#include <epoxy/gl.h>
#include <fmt/core.h>
#include <nlohmann/json.hpp>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

namespace terrain::view {
namespace {

constexpr double kErrorStep = 1.25;
constexpr std::chrono::seconds kSettleTimeout{60};
constexpr std::size_t kGlErrorsPrinted = 10;

std::string displayName(const std::filesystem::path& pyramid) {
    std::filesystem::path p = pyramid;
    if (!p.has_filename()) p = p.parent_path();  // "dem.pyramid/"
    return p.filename().string();
}

}  // namespace

Result<std::unique_ptr<Viewer>> Viewer::create(const ViewerOptions& options) {
    // Everything that can be checked without a window is checked first, so a typo in a file
    // name gives a message rather than a window that flashes and closes.
    auto manifest = io::readManifest(options.pyramid);
    if (!manifest) return manifest.error();
    std::unique_ptr<Viewer> viewer(new Viewer(options, tools::SurfaceKit::of(manifest.value())));

    if (!options.pathFile.empty()) {
        auto path = runtime::FlightPath::load(options.pathFile, viewer->m_kit->pathFrame());
        if (!path) return path.error();
        viewer->m_path = std::move(path).value();
    }
    const std::pair<const std::string&, const char*> outputs[] = {
        {options.screenshotFile, "screenshot"},
        {options.recordFile, "camera path"},
        {options.telemetryFile, "telemetry log"}};
    for (const auto& [file, what] : outputs) {
        if (file.empty()) continue;
        if (auto ok = checkOutputFolder(file, what); !ok) return ok.error();
    }

    gl::GlfwWindowOptions windowOptions;
    windowOptions.vsync = options.vsync;
    auto window =
        gl::GlfwWindowContext::create(options.widthPx, options.heightPx,
                                      "terrain-view - " + viewer->m_pyramidName, windowOptions);
    if (!window) {
        return Error{window.error().message +
                     "\nterrain-view needs a display with OpenGL 4.5 core (without a "
                     "display, run it under `xvfb-run -a`; terrain-render renders headless)"};
    }
    viewer->m_window = std::move(window).value();

    if (auto opened = viewer->openSession(options.budgets.cpuCacheMiB, options.budgets.gpuLayers);
        !opened) {
        return opened.error();
    }
    auto imgui = ImGuiLayer::create(viewer->m_window->window());
    if (!imgui) return imgui.error();
    viewer->m_imgui = std::move(imgui).value();
    viewer->m_input = std::make_unique<WindowInput>(viewer->m_window->window(), *viewer->m_imgui);

    viewer->initialCamera();
    if (!options.telemetryFile.empty()) {
        if (auto started = viewer->startTelemetryLog(); !started) return started.error();
    }
    if (!options.recordFile.empty()) viewer->toggleRecording();
    return viewer;
}

Viewer::Viewer(const ViewerOptions& options, std::unique_ptr<tools::SurfaceKit> kit)
    : m_options(options),
      m_pyramidName(displayName(options.pyramid)),
      m_kit(std::move(kit)),
      m_recordNames(options.recordFile, "terrain-view-path", ".camera.json"),
      m_screenshotNames(options.screenshotFile, "terrain-view", ".png"),
      m_telemetryNames(options.telemetryFile, "terrain-view-telemetry", ".csv") {
    m_settings.errorPx = options.errorPx;
    m_settings.debugView = options.look.debugViewValue();
    m_settings.wireframe = options.look.wireframe;
    m_settings.skirts = !options.look.noSkirts;
    m_settings.fog = !options.noFog;
    m_settings.imagery = !options.look.noImagery;
    m_settings.imageryLit = !options.look.imageryUnlit;
    for (std::size_t l = 0; l < m_settings.imageryOpacity.size(); ++l)
        if (l < options.look.imageryOpacity.size())
            m_settings.imageryOpacity[l] = options.look.imageryOpacity[l];
    m_settings.vsync = options.vsync;
    m_settings.measureEvery = std::max(1, options.measureEvery);
    m_settings.overlayVisible = !options.hideOverlay;
    m_settings.cpuCacheMiB = options.budgets.cpuCacheMiB;
    m_settings.gpuLayers = options.budgets.gpuLayers;
}

Viewer::~Viewer() {
    // The overlay and input go before the session, the session before the window (members
    // are declared in that order); a recording or log still open is finished by run().
    m_input.reset();
    m_imgui.reset();
    m_controls.reset();
    m_session.reset();
}

Status Viewer::openSession(double cpuCacheMiB, int gpuLayers) {
    runtime::TerrainSessionOptions options;
    // The overlay changes the cache budgets; the upload budget stays the command line's.
    tools::StreamingBudgets budgets = m_options.budgets;
    budgets.cpuCacheMiB = cpuCacheMiB;
    budgets.gpuLayers = gpuLayers;
    budgets.applyTo(options.streaming);
    budgets.applyTo(options.lod);
    options.lod.errorPx = m_settings.errorPx;
    if (auto method = runtime::parseLodMethod(m_options.method)) options.method = method.value();
    auto opened = runtime::TerrainSession::open(m_options.pyramid, options);
    if (!opened) return opened.error();
    m_session = std::move(opened).value();
    if (m_controls) m_controls->attach(*m_session);
    m_appliedCpuCacheMiB = cpuCacheMiB;
    m_appliedGpuLayers = gpuLayers;
    // A new session starts with a live LOD and ε as set.
    m_settings.lodFrozen = false;
    m_applied.lodFrozen = false;
    m_applied.errorPx = m_settings.errorPx;
    return {};
}

void Viewer::reopenSession() {
    const double previousMiB = m_appliedCpuCacheMiB;
    const int previousLayers = m_appliedGpuLayers;
    m_session.reset();  // frees the GPU pool before the new one is made
    if (auto opened = openSession(m_settings.cpuCacheMiB, m_settings.gpuLayers); opened) {
        setStatus(fmt::format("re-opened with CPU cache {:.0f} MiB, {} GPU layers",
                              m_settings.cpuCacheMiB, m_settings.gpuLayers));
        return;
    } else {
        const std::string why = opened.error().message;
        if (auto back = openSession(previousMiB, previousLayers); !back) {
            // Neither the new nor the old budgets open: nothing to draw, so stop.
            setStatus(
                why + "; re-opening with the previous budgets failed too: " + back.error().message,
                true);
            std::fprintf(stderr, "terrain-view: %s\n", m_status.c_str());
            m_quit = true;
            m_exitFilesFailed = true;
            return;
        }
        m_settings.cpuCacheMiB = previousMiB;
        m_settings.gpuLayers = previousLayers;
        setStatus("cannot apply the budgets: " + why + " (kept the previous ones)", true);
    }
}

void Viewer::initialCamera() {
    m_camera.viewportWidth = std::max(1, m_options.widthPx);
    m_camera.viewportHeight = std::max(1, m_options.heightPx);
    // A path, when given, sets the start: --orbit and --goto are for a flight by hand.
    ViewerOptions controlOptions = m_options;
    if (m_path) {
        controlOptions.orbit = false;
        controlOptions.jumpTo.clear();
    }
    m_controls = ViewControls::create(*m_session, controlOptions);
    // The surface's sky and fog (none on a globe: a fog scaled to a DEM would hide the
    // planet from orbit); the fog starts on where the surface has one and --no-fog is not given.
    m_kit->skyAndFog(m_style, m_options.look, m_session->surface());
    m_settings.fogDensityPerM = m_style.fogDensityPerM;
    m_settings.fog = m_settings.fog && m_style.fogDensityPerM > 0.0f;
    if (std::string status = m_controls->start(m_camera, m_settings); !status.empty())
        setStatus(std::move(status));
    if (m_path) {
        m_path->apply(m_path->startS(), m_camera);
        m_controls->placed(m_camera);
        m_pathTimeS = m_path->startS();
        m_playing = true;
    }
}

void Viewer::reportFaults() {
    m_faultPrinter.printNew(m_session->streamer());
    const runtime::TileFault* fatal = m_session->fatalFault();
    if (fatal == nullptr || m_fatalFaultShown) return;
    // Nothing can be drawn: said on screen (the overlay shown) and in the exit status.
    m_fatalFaultShown = true;
    m_settings.overlayVisible = true;
    setStatus(std::string(m_kit->rootFaultMessage()) + fatal->message, true);
}

void Viewer::setStatus(std::string message, bool error) {
    if (error) std::fprintf(stderr, "terrain-view: %s\n", message.c_str());
    m_status = std::move(message);
    m_statusIsError = error;
}

void Viewer::handle(ViewerAction action) {
    using A = ViewerAction;
    switch (action) {
        case A::ToggleOverlay:
            m_settings.overlayVisible = !m_settings.overlayVisible;
            break;
        case A::Screenshot:
            m_screenshotRequested = true;
            break;
        case A::ToggleFreezeLod:
            m_settings.lodFrozen = !m_settings.lodFrozen;
            break;
        case A::ToggleTelemetryLog:
            toggleTelemetryLog();
            break;
        case A::ToggleOrbit:
            if (std::string status = m_controls->toggleOrbit(m_camera, m_scene); status.empty()) {
                m_playing = false;
            } else {
                setStatus(std::move(status));
            }
            break;
        case A::ToggleRecording:
            toggleRecording();
            break;
        case A::ViewShaded:
            m_settings.debugView = runtime::TerrainDebugView::Shaded;
            break;
        case A::ViewLevel:
            m_settings.debugView = runtime::TerrainDebugView::Level;
            break;
        case A::ViewTessFactor:
            m_settings.debugView = runtime::TerrainDebugView::TessFactor;
            break;
        case A::ToggleWireframe:
            m_settings.wireframe = !m_settings.wireframe;
            break;
        case A::ToggleSkirts:
            m_settings.skirts = !m_settings.skirts;
            break;
        case A::ToggleFog:
            m_settings.fog = !m_settings.fog;
            break;
        case A::ToggleVsync:
            m_settings.vsync = !m_settings.vsync;
            break;
        case A::ToggleFloor:
            m_settings.keepAboveGround = !m_settings.keepAboveGround;
            break;
        case A::PlayPause:
            if (!m_path) {
                setStatus("no camera path to play (open one with --path FILE)");
            } else {
                if (!m_playing && m_pathTimeS >= m_path->endS()) m_pathTimeS = m_path->startS();
                m_playing = !m_playing;
            }
            break;
        case A::RestartPath:
            if (m_path) {
                m_pathTimeS = m_path->startS();
                m_playing = true;
            }
            break;
        case A::Home:
            m_playing = false;
            m_controls->home(m_camera);
            break;
        case A::FinerError:
            m_settings.errorPx =
                std::max(ViewerSettings::kMinErrorPx, m_settings.errorPx / kErrorStep);
            break;
        case A::CoarserError:
            m_settings.errorPx =
                std::min(ViewerSettings::kMaxErrorPx, m_settings.errorPx * kErrorStep);
            break;
        case A::OpenJump:
            m_settings.overlayVisible = true;
            m_overlay.focusJump();
            break;
        case A::Quit:
            m_quit = true;
            break;
    }
}

void Viewer::applySettings() {
    if (m_settings.errorPx != m_applied.errorPx) {
        runtime::LodOptions lod = m_session->lodOptions();
        lod.errorPx = m_settings.errorPx;
        m_session->setLodOptions(lod);
    }
    if (m_settings.lodFrozen != m_applied.lodFrozen) m_session->setLodFrozen(m_settings.lodFrozen);
    if (m_settings.vsync != m_applied.vsync) m_window->setVsync(m_settings.vsync);
    m_controls->apply(m_settings);

    m_style.debugView = m_settings.debugView;
    m_style.wireframe = m_settings.wireframe;
    m_style.skirts = m_settings.skirts;
    m_style.fogDensityPerM = m_settings.fog ? m_settings.fogDensityPerM : 0.0f;
    m_style.imagery = m_settings.imagery;
    m_style.imageryLighting = m_settings.imageryLit;
    m_style.imageryOrder = m_settings.imageryOrder;
    for (std::size_t l = 0; l < m_style.imageryOpacity.size(); ++l)
        m_style.imageryOpacity[l] =
            m_settings.imageryShown[l] ? m_settings.imageryOpacity[l] : 0.0f;
    m_applied = m_settings;
}

void Viewer::moveCamera(const runtime::CameraInput& input, double dtS) {
    if (m_playing && input.any()) {
        m_playing = false;  // the user takes the controls from the path
        setStatus("path paused: Space resumes it");
    }
    if (m_playing) {
        m_pathTimeS = std::min(m_pathTimeS + dtS, m_path->endS());
        m_path->apply(m_pathTimeS, m_camera);
        m_controls->placed(m_camera);
        if (m_pathTimeS >= m_path->endS()) {
            m_playing = false;
            setStatus("path finished: Space plays it again");
        }
        return;
    }
    m_controls->move(m_camera, input, *m_input, m_timeS, dtS);
}

void Viewer::orbitAt(double xPx, double yPx, bool fallbackAhead) {
    if (std::string status = m_controls->orbitAt(m_camera, m_scene, xPx, yPx, fallbackAhead);
        !status.empty()) {
        setStatus(std::move(status));
        return;
    }
    m_playing = false;
}

void Viewer::jump() {
    m_playing = false;
    setStatus(m_controls->jump(m_camera, m_settings, m_timeS));
}

void Viewer::toggleRecording() {
    if (!m_recorder.recording()) {
        m_recordingFile = m_recordNames.next();
        m_recorder.start(m_kit->pathFrame(), m_timeS, m_camera);
        setStatus("recording the camera path to " + m_recordingFile.string());
        return;
    }
    auto path = m_recorder.finish(m_timeS, m_camera);
    if (!path) {
        setStatus(m_recordingFile.string() + ": " + path.error().message, true);
        m_exitFilesFailed = true;
        return;
    }
    if (auto saved = path.value().save(m_recordingFile); !saved) {
        setStatus(saved.error().message, true);
        m_exitFilesFailed = true;
        return;
    }
    m_pathsRecorded.push_back(m_recordingFile.string());
    setStatus(fmt::format("camera path saved: {} ({} keyframes, {:.1f} s)",
                          m_recordingFile.string(), m_recorder.keyframeCount(),
                          path.value().durationS()));
}

Status Viewer::startTelemetryLog() {
    const std::filesystem::path file = m_telemetryNames.next();
    auto writer = runtime::TelemetryCsvWriter::create(file);
    if (!writer) return writer.error();
    m_csv = std::move(writer).value();
    m_logFileText = file.string();
    setStatus("logging telemetry to " + m_logFileText);
    return {};
}

void Viewer::toggleTelemetryLog() {
    if (!m_csv) {
        if (auto started = startTelemetryLog(); !started) setStatus(started.error().message, true);
        return;
    }
    const std::uint64_t rows = m_csv->rowCount();
    const Status closed = m_csv->close();
    m_csv.reset();
    if (!closed) {
        setStatus(closed.error().message, true);
        m_exitFilesFailed = true;
        return;
    }
    m_telemetryWritten.push_back(m_logFileText);
    setStatus(fmt::format("telemetry log written: {} ({} frames)", m_logFileText, rows));
}

void Viewer::takeScreenshot(const std::filesystem::path& path) {
    const gl::FramebufferSize size = m_window->framebufferSize();
    if (auto written = writeWindowScreenshot(path, size.width, size.height); !written) {
        setStatus(written.error().message, true);
        m_exitFilesFailed = true;
        return;
    }
    m_screenshotsWritten.push_back(path.string());
    setStatus("screenshot written: " + path.string());
}

void Viewer::checkGlErrors() {
    const gl::GlDebugLog& log = m_window->debugLog();
    if (log.errorCount() <= m_glErrorsReported) return;
    if (m_glErrorsReported < kGlErrorsPrinted) {
        const std::vector<gl::GlDebugMessage> errors = log.errors();
        for (std::size_t i = m_glErrorsReported; i < errors.size() && i < kGlErrorsPrinted; ++i) {
            std::fprintf(stderr, "terrain-view: %s\n", errors[i].describe().c_str());
        }
    }
    m_glErrorsReported = log.errorCount();
    m_status = fmt::format("OpenGL reported {} error(s); see the terminal", m_glErrorsReported);
    m_statusIsError = true;
}

OverlayModel Viewer::overlayModel(const runtime::FrameTelemetry& frame) const {
    OverlayModel m;
    m.pyramidName = m_pyramidName;
    m.gl = &m_window->info();
    m.framebufferWidth = m_scene.width();
    m.framebufferHeight = m_scene.height();
    m.history = &m_history;
    m.frame = &frame;
    m.gpuLayersCapacity = m_appliedGpuLayers;
    m.cpuCacheBudgetMiB = m_appliedCpuCacheMiB;
    m.lodNodes = m_session->lodStats().nodes;
    for (const io::ManifestImageryLayer& layer : m_session->manifest().imagery)
        m.imageryNames.push_back(layer.name);
    m.glErrors = m_glErrorsReported;
    m.camera = &m_camera;
    m.controls = m_controls.get();
    m.havePath = m_path.has_value();
    m.playing = m_playing;
    if (m_path) {
        m.pathTimeS = m_pathTimeS - m_path->startS();
        m.pathDurationS = m_path->durationS();
        m.pathName = m_options.pathFile;
    }
    m.recording = m_recorder.recording();
    m.recordedKeyframes = m_recorder.keyframeCount();
    m.recordedS = m_recorder.recordedS();
    m.logging = m_csv.has_value();
    if (m_csv) {
        m.logRows = m_csv->rowCount();
        m.logFile = m_logFileText;
    }
    m.status = m_status;
    m.statusIsError = m_statusIsError;
    return m;
}

int Viewer::run() {
    const auto start = Clock::now();
    auto previousEnd = start;
    auto previousStart = start;
    std::vector<OverlayWindowRect> lastWindows;

    while (true) {
        glfwPollEvents();
        const auto frameStart = Clock::now();
        const double wallS = std::chrono::duration<double>(frameStart - start).count();
        double dtS = m_options.fixedFps > 0.0
                         ? 1.0 / m_options.fixedFps
                         : std::chrono::duration<double>(frameStart - previousStart).count();
        if (m_frame == 0) dtS = 0.0;  // the first frame shows the start of the flight
        previousStart = frameStart;

        const bool last = m_quit || m_window->shouldClose() ||
                          (m_options.frames > 0 && m_frame + 1 >= m_options.frames) ||
                          (m_options.exitAfterS > 0.0 && wallS >= m_options.exitAfterS);

        const gl::FramebufferSize size = m_window->framebufferSize();
        if (size.width <= 0 || size.height <= 0) {
            glfwWaitEventsTimeout(0.1);  // minimised: nothing to draw
            if (last) break;
            continue;
        }
        if (auto resized = m_scene.resize(size.width, size.height); !resized) {
            std::fprintf(stderr, "terrain-view: %s\n", resized.error().message.c_str());
            return 1;
        }
        m_camera.viewportWidth = size.width;
        m_camera.viewportHeight = size.height;

        // Input: actions first (they may pick from the last frame's depth, taken with the
        // camera as it still is), then the motion of this frame.
        for (ViewerAction action : m_input->takeActions()) handle(action);
        if (auto click = m_input->takeOrbitClick()) orbitAt(click->x, click->y, false);
        m_timeS += dtS;
        const runtime::CameraInput input = m_input->takeCameraInput();
        moveCamera(input, dtS);
        if (m_recorder.recording()) m_recorder.sample(m_timeS, m_camera);
        applySettings();

        // The frame protocol of TerrainSession.
        if (m_options.settle) m_session->settle(m_camera, kSettleTimeout);
        m_session->beginFrame(m_camera);
        m_scene.beginScene(m_style.skyColor);
        m_style.measure =
            m_frame % static_cast<std::uint64_t>(m_settings.measureEvery) == 0 || last;
        m_session->draw(m_camera, m_style);
        m_scene.presentToWindow();
        runtime::FrameTelemetry t;
        m_session->endFrame(t);
        reportFaults();

        // The overlay on top, in the window's framebuffer.
        m_imgui->newFrame();
        const OverlayModel model = overlayModel(t);
        const OverlayRequests requests = m_overlay.draw(model, m_settings);
        glViewport(0, 0, size.width, size.height);
        m_imgui->render();
        lastWindows = m_overlay.windows();

        if (m_screenshotRequested) {
            m_screenshotRequested = false;
            takeScreenshot(m_screenshotNames.nextKeyed());
        }
        if (last && !m_options.screenshotFile.empty()) {
            takeScreenshot(m_screenshotNames.takeNamed());
        }
        m_window->swapBuffers();

        const auto end = Clock::now();
        t.frame = m_frame;
        t.timeS = std::chrono::duration<double>(end - start).count();
        t.frameMs = std::chrono::duration<double, std::milli>(end - previousEnd).count();
        previousEnd = end;
        if (m_csv) m_csv->write(t);
        m_summary.add(t);
        m_history.add(t);
        checkGlErrors();
        ++m_frame;

        for (ViewerAction action : requests.actions) handle(action);
        if (requests.jump) jump();
        if (requests.applyBudgets) reopenSession();
        if (last) break;
    }

    const double wallS = std::chrono::duration<double>(Clock::now() - start).count();
    const bool filesOk = finishExitFiles();
    m_summary.mergeLoadLatencies(m_session->streamer().loadLatencies());
    m_session->streamer().drain(std::chrono::seconds(10));
    if (m_options.json) {
        nlohmann::json windows = nlohmann::json::array();
        for (const OverlayWindowRect& w : lastWindows) {
            windows.push_back({{"name", w.name},
                               {"x", w.x},
                               {"y", w.y},
                               {"width", w.width},
                               {"height", w.height}});
        }
        const gl::FramebufferSize size = m_window->framebufferSize();
        const nlohmann::json out{
            {"tool", "terrain-view"},
            {"pyramid", m_options.pyramid},
            {"tiling", std::string(runtime::surfaceName(m_session->surface().kind()))},
            {"frames", m_frame},
            {"seconds", wallS},
            {"width_px", size.width},
            {"height_px", size.height},
            {"error_px", m_settings.errorPx},
            {"method", m_options.method},
            {"vsync", m_settings.vsync},
            {"fixed_fps",
             m_options.fixedFps > 0.0 ? nlohmann::json(m_options.fixedFps) : nlohmann::json()},
            {"path", m_path ? nlohmann::json(m_options.pathFile) : nlohmann::json()},
            {"path_time_s",
             m_path ? nlohmann::json(m_pathTimeS - m_path->startS()) : nlohmann::json()},
            {"paths_recorded", m_pathsRecorded},
            {"screenshots", m_screenshotsWritten},
            {"telemetry_csv", m_telemetryWritten},
            {"overlay", {{"visible", m_settings.overlayVisible}, {"windows", windows}}},
            {"camera", m_controls->cameraJson(m_camera)},
            {"lod_frozen", m_settings.lodFrozen},
            {"triangles_last_measured", m_history.latestTriangles()
                                            ? nlohmann::json(*m_history.latestTriangles())
                                            : nlohmann::json()},
            {"draw_calls_last", m_history.empty() ? 0 : m_history.latest().drawCalls},
            {"patches_drawn_last", m_history.empty() ? 0 : m_history.latest().patchesDrawn},
            {"gl_errors", m_glErrorsReported},
            {"telemetry", m_summary.toJson()},
            {"gl", tools::glInfoJson(*m_window)},
        };
        std::puts(out.dump(2).c_str());
    }
    printSummary(wallS);
    if (m_glErrorsReported > 0) {
        std::fprintf(stderr, "terrain-view: OpenGL reported %zu error(s):\n%s", m_glErrorsReported,
                     m_window->debugLog().formatErrors().c_str());
        return 1;
    }
    m_faultPrinter.printRest(m_session->streamer());
    return filesOk && !m_exitFilesFailed && !m_fatalFaultShown ? 0 : 1;
}

bool Viewer::finishExitFiles() {
    bool ok = true;
    if (m_recorder.recording()) {
        toggleRecording();
        ok = ok && !m_statusIsError;
    }
    if (m_csv) {
        toggleTelemetryLog();
        ok = ok && !m_statusIsError;
    }
    return ok;
}

void Viewer::printSummary(double wallS) const {
    const auto fps = m_frame > 0 && wallS > 0.0 ? static_cast<double>(m_frame) / wallS : 0.0;
    std::fprintf(stderr,
                 "terrain-view: %llu frames in %.1f s (%.1f fps) over %s, ε = %.2f px; %zu "
                 "screenshot(s), %zu telemetry log(s), %zu camera path(s) written\n",
                 static_cast<unsigned long long>(m_frame), wallS, fps, m_pyramidName.c_str(),
                 m_settings.errorPx, m_screenshotsWritten.size(), m_telemetryWritten.size(),
                 m_pathsRecorded.size());
}

}  // namespace terrain::view
