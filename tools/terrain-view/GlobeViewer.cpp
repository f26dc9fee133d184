#include "GlobeViewer.h"

#include "KeyBindings.h"
#include "Screenshot.h"
#include "terrain/globe/Wgs84.h"
#include "terrain/pyramid/GlobeLayout.h"
#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/runtime/GlobeDrawnGround.h"
#include "terrain/runtime/ScreenProjection.h"

#include <GLFW/glfw3.h>
#include <epoxy/gl.h>
#include <fmt/core.h>
#include <imgui.h>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>

namespace terrain::view {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kDegree = std::numbers::pi / 180.0;
constexpr std::array<float, 3> kSpace{0.02f, 0.03f, 0.08f};

}  // namespace

Result<std::unique_ptr<GlobeViewer>> GlobeViewer::create(const ViewerOptions& options) {
    auto manifest = io::readManifest(options.pyramid);
    if (!manifest) return manifest.error();
    if (!manifest.value().globe) return Error{options.pyramid + ": not a globe pyramid"};
    std::unique_ptr<GlobeViewer> viewer(new GlobeViewer(options));
    gl::GlfwWindowOptions windowOptions;
    windowOptions.vsync = options.vsync;
    auto window = gl::GlfwWindowContext::create(options.widthPx, options.heightPx,
                                                "terrain-view - " + options.pyramid, windowOptions);
    if (!window)
        return Error{window.error().message +
                     "\nterrain-view needs a display with OpenGL 4.5 core (without a display, run "
                     "it under `xvfb-run -a`; terrain-render renders headless)"};
    viewer->m_window = std::move(window).value();
    runtime::TerrainSessionOptions sessionOptions;
    options.budgets.applyTo(sessionOptions.streaming);
    sessionOptions.lod.errorPx = options.errorPx;
    auto session = runtime::TerrainSession::open(options.pyramid, sessionOptions);
    if (!session) return session.error();
    viewer->m_session = std::move(session).value();
    auto imgui = ImGuiLayer::create(viewer->m_window->window());
    if (!imgui) return imgui.error();
    viewer->m_imgui = std::move(imgui).value();
    viewer->m_input = std::make_unique<WindowInput>(viewer->m_window->window(), *viewer->m_imgui);

    viewer->m_camera.fovY = 50.0 * kDegree;
    const io::ManifestGlobe& g = *manifest.value().globe;
    viewer->m_pose = runtime::GlobeController::overExtent(g.west, g.south, g.east, g.north,
                                                          viewer->m_camera.fovY);
    if (options.jumpTo.size() >= 2) {  // --goto LAT,LON[,ALTITUDE]
        viewer->m_pose.where = {options.jumpTo[0], options.jumpTo[1],
                                options.jumpTo.size() > 2 ? options.jumpTo[2] : 10000.0};
        viewer->m_pose.pitchDeg = -30.0;
    }
    viewer->m_flyTo = {viewer->m_pose.where.latitudeDeg, viewer->m_pose.where.longitudeDeg,
                       10000.0};
    viewer->m_style.skyColor = kSpace;
    viewer->m_style.debugView = options.look.debugViewValue();
    viewer->m_style.wireframe = options.look.wireframe;
    viewer->m_style.skirts = !options.look.noSkirts;
    viewer->m_overlayVisible = !options.hideOverlay;
    return viewer;
}

GlobeViewer::~GlobeViewer() {
    m_input.reset();
    m_imgui.reset();
    m_session.reset();
}

std::optional<globe::Geodetic> GlobeViewer::groundUnderPixel(double xPx, double yPx) const {
    const glm::dmat4 inverse = glm::inverse(m_camera.relativeViewProjection());
    const int x = static_cast<int>(xPx);
    const int y = m_camera.viewportHeight - 1 - static_cast<int>(yPx);  // rows bottom-up
    const glm::dvec3 direction = glm::normalize(runtime::unprojectPixel(
        inverse, m_camera.viewportWidth, m_camera.viewportHeight, x, y, 0.5));
    const glm::dvec3 radii(globe::Wgs84::kEquatorialRadius, globe::Wgs84::kEquatorialRadius,
                           globe::Wgs84::kPolarRadius);
    const glm::dvec3 o = m_camera.position / radii, d = direction / radii;
    const double a = glm::dot(d, d), b = glm::dot(o, d), c = glm::dot(o, o) - 1.0;
    const double discriminant = b * b - a * c;
    if (discriminant < 0.0 || c < 0.0) return std::nullopt;
    const double t = (-b - std::sqrt(discriminant)) / a;
    if (t <= 0.0) return std::nullopt;
    return globe::Wgs84::toGeodetic(m_camera.position + t * direction);
}

double GlobeViewer::floorUnderCamera() const {
    // The ground the finest resident data draws under the camera, its tile looked up in the
    // CPU cache (no read); a patch whose tile has left that cache counts its highest point.
    const runtime::TileStreamer& streamer = m_session->streamer();
    const runtime::GlobeGroundLookup lookup{
        .residentInfo =
            [&streamer](const globe::GlobePatchId& id) {
                return streamer.residentInfo(io::layoutPatchOf(id));
            },
        .cachedTile =
            [&streamer](const globe::GlobePatchId& id) {
                return streamer.cpuCache().peek(io::layoutPatchOf(id));
            }};
    return runtime::residentGroundHeight(m_camera.position, streamer.layout(), lookup);
}

void GlobeViewer::drawOverlay(const runtime::FrameTelemetry& t) {
    if (!m_overlayVisible) return;
    ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
    ImGui::Begin("Globe");
    ImGui::Text("%.5f°, %.5f°, %.0f m above WGS84", m_pose.where.latitudeDeg,
                m_pose.where.longitudeDeg, m_pose.where.height);
    ImGui::Text("heading %.1f°, pitch %.1f°", m_pose.headingDeg, m_pose.pitchDeg);
    const runtime::LodUpdateStats& lod = m_session->lodStats();
    ImGui::Text("patches %llu (%llu virtual, %llu bare), %llu behind the horizon",
                static_cast<unsigned long long>(lod.drawn),
                static_cast<unsigned long long>(lod.drawnVirtual),
                static_cast<unsigned long long>(lod.drawnBare),
                static_cast<unsigned long long>(lod.horizonCulled));
    ImGui::Text("LOD %.0f µs, loads queued %llu", m_session->lodUpdateUs(),
                static_cast<unsigned long long>(t.queueDepth));
    float errorPx = static_cast<float>(m_session->errorPx());
    if (ImGui::SliderFloat("error (px)", &errorPx, 0.5f, 16.0f)) {
        m_session->setErrorPx(errorPx);
    }
    const io::PyramidManifest& m = m_session->manifest();
    if (ImGui::Button("Go to the data"))
        m_pose = runtime::GlobeController::overExtent(m.globe->west, m.globe->south, m.globe->east,
                                                      m.globe->north, m_camera.fovY);
    ImGui::SameLine();
    if (ImGui::Button("Whole Earth"))
        m_pose = runtime::GlobeController::wholeEarth(m_pose.where.latitudeDeg,
                                                      m_pose.where.longitudeDeg);
    ImGui::InputDouble("latitude", &m_flyTo[0], 0.0, 0.0, "%.5f");
    ImGui::InputDouble("longitude", &m_flyTo[1], 0.0, 0.0, "%.5f");
    ImGui::InputDouble("altitude (m)", &m_flyTo[2], 0.0, 0.0, "%.0f");
    if (ImGui::Button("Fly there")) {
        m_pose.where = {std::clamp(m_flyTo[0], -90.0, 90.0), m_flyTo[1], std::max(m_flyTo[2], 1.0)};
        m_pose.pitchDeg = -30.0;
    }
    ImGui::TextUnformatted("drag: spin  Shift-drag: look  wheel: zoom to cursor  WASD/QE: fly");
    ImGui::TextUnformatted("H: go to the data  F12: screenshot  Esc: quit");
    if (!m_status.empty()) ImGui::TextUnformatted(m_status.c_str());
    ImGui::End();
}

int GlobeViewer::run() {
    const auto start = Clock::now();
    auto previous = start;
    std::uint64_t frame = 0;
    int status = 0;
    bool fatalShown = false;
    while (true) {
        glfwPollEvents();
        const auto now = Clock::now();
        double dtS = m_options.fixedFps > 0.0
                         ? 1.0 / m_options.fixedFps
                         : std::chrono::duration<double>(now - previous).count();
        if (frame == 0) dtS = 0.0;
        previous = now;
        const double wallS = std::chrono::duration<double>(now - start).count();
        const bool last = m_quit || m_window->shouldClose() ||
                          (m_options.frames > 0 && frame + 1 >= m_options.frames) ||
                          (m_options.exitAfterS > 0.0 && wallS >= m_options.exitAfterS);
        const gl::FramebufferSize size = m_window->framebufferSize();
        if (size.width <= 0 || size.height <= 0) {
            glfwWaitEventsTimeout(0.1);
            if (last) break;
            continue;
        }
        if (auto resized = m_scene.resize(size.width, size.height); !resized) {
            std::fprintf(stderr, "terrain-view: %s\n", resized.error().message.c_str());
            return 1;
        }
        m_camera.viewportWidth = size.width;
        m_camera.viewportHeight = size.height;

        for (ViewerAction action : m_input->takeActions()) {
            switch (action) {
                case ViewerAction::Quit:
                    m_quit = true;
                    break;
                case ViewerAction::ToggleOverlay:
                    m_overlayVisible = !m_overlayVisible;
                    break;
                case ViewerAction::Home: {
                    const io::ManifestGlobe& g = *m_session->manifest().globe;
                    m_pose = runtime::GlobeController::overExtent(g.west, g.south, g.east, g.north,
                                                                  m_camera.fovY);
                    break;
                }
                case ViewerAction::Screenshot: {
                    const std::string file = fmt::format("terrain-view-globe-{}.png", frame);
                    const Status written = writeWindowScreenshot(file, size.width, size.height);
                    m_status = written ? "screenshot written: " + file : written.error().message;
                    break;
                }
                case ViewerAction::ViewShaded:
                    m_style.debugView = runtime::TerrainDebugView::Shaded;
                    break;
                case ViewerAction::ViewLevel:
                    m_style.debugView = runtime::TerrainDebugView::Level;
                    break;
                case ViewerAction::ViewTessFactor:
                    m_style.debugView = runtime::TerrainDebugView::TessFactor;
                    break;
                case ViewerAction::ToggleWireframe:
                    m_style.wireframe = !m_style.wireframe;
                    break;
                case ViewerAction::ToggleSkirts:
                    m_style.skirts = !m_style.skirts;
                    break;
                default:
                    break;  // the planar viewer's path, orbit and LOD actions
            }
        }
        runtime::GlobeControlInput control;
        control.held = m_input->takeCameraInput();
        control.lookAround = control.held.boost && m_input->dragging();
        if (control.lookAround) control.held.boost = false;
        control.focalPx = 0.5 * double(size.height) / std::tan(0.5 * m_camera.fovY);
        if (control.held.wheelSteps != 0.0) {
            double cx = 0.0, cy = 0.0;
            glfwGetCursorPos(m_window->window(), &cx, &cy);
            int windowWidth = 1, windowHeight = 1;
            glfwGetWindowSize(m_window->window(), &windowWidth, &windowHeight);
            control.zoomToward = groundUnderPixel(cx * size.width / std::max(windowWidth, 1),
                                                  cy * size.height / std::max(windowHeight, 1));
        }
        m_controller.update(m_pose, control, dtS, floorUnderCamera());
        runtime::placeOnGlobe(m_camera, m_pose);

        if (m_options.settle) m_session->settle(m_camera, std::chrono::seconds(60));
        m_session->beginFrame(m_camera);
        m_scene.beginScene(m_style.skyColor);
        m_style.measure = last;
        m_session->draw(m_camera, m_style);
        m_scene.presentToWindow();
        runtime::FrameTelemetry t;
        m_session->endFrame(t);
        m_faultPrinter.printNew(m_session->streamer());
        if (const runtime::TileFault* fatal = m_session->fatalFault(); fatal && !fatalShown) {
            // A face without its data: said on screen (the overlay shown), on stderr and in
            // the exit status.
            m_status =
                "a cube face's data cannot be drawn, its root patch failed: " + fatal->message;
            std::fprintf(stderr, "terrain-view: %s\n", m_status.c_str());
            m_overlayVisible = true;
            fatalShown = true;
            status = 1;
        }
        m_imgui->newFrame();
        drawOverlay(t);
        glViewport(0, 0, size.width, size.height);
        m_imgui->render();
        if (last && !m_options.screenshotFile.empty()) {
            if (Status written =
                    writeWindowScreenshot(m_options.screenshotFile, size.width, size.height);
                !written) {
                std::fprintf(stderr, "terrain-view: %s\n", written.error().message.c_str());
                status = 1;
            }
        }
        m_window->swapBuffers();
        if (m_window->debugLog().errorCount() > 0) {
            std::fprintf(stderr, "terrain-view: OpenGL reported an error:\n%s\n",
                         m_window->debugLog().formatErrors().c_str());
            return 1;
        }
        ++frame;
        if (last) break;
    }
    m_session->streamer().drain(std::chrono::seconds(10));
    m_faultPrinter.printRest(m_session->streamer());
    if (m_options.json) {
        const nlohmann::json summary{
            {"tool", "terrain-view"},
            {"pyramid", m_options.pyramid},
            {"tiling", "globe"},
            {"frames", frame},
            {"camera",
             {{"latitude", m_pose.where.latitudeDeg},
              {"longitude", m_pose.where.longitudeDeg},
              {"altitude_m", m_pose.where.height},
              {"heading_deg", m_pose.headingDeg},
              {"pitch_deg", m_pose.pitchDeg}}},
            {"patches_drawn", m_session->lodStats().drawn},
            {"screenshot", m_options.screenshotFile.empty()
                               ? nlohmann::json()
                               : nlohmann::json(m_options.screenshotFile)},
        };
        std::puts(summary.dump(2).c_str());
    }
    return status;
}

}  // namespace terrain::view
