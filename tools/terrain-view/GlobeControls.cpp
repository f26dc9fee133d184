#include "GlobeControls.h"

#include "OverlayWidgets.h"
#include "ViewerOverlay.h"

#include "terrain/pyramid/GlobeLayout.h"
#include "terrain/runtime/GlobeDrawnGround.h"
#include "terrain/runtime/ScreenProjection.h"

#include <fmt/core.h>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace terrain::view {
namespace {

constexpr double kDegree = std::numbers::pi / 180.0;
constexpr std::array<float, 3> kSpace{0.02f, 0.03f, 0.08f};
constexpr double kFlyToPitchDeg = -30.0;
constexpr double kDefaultAltitudeM = 10000.0;

runtime::GlobePose overData(const io::PyramidManifest& manifest, double fovY) {
    const io::ManifestGlobe& g = *manifest.globe;
    return runtime::GlobeController::overExtent(g.west, g.south, g.east, g.north, fovY);
}

}  // namespace

GlobeControls::GlobeControls(const runtime::TerrainSession& session, const ViewerOptions& options)
    : m_options(options) {
    attach(session);
}

void GlobeControls::attach(const runtime::TerrainSession& session) { m_session = &session; }

std::string GlobeControls::start(runtime::Camera& camera, ViewerSettings& settings) {
    camera.fovY = 50.0 * kDegree;
    m_pose = overData(m_session->manifest(), camera.fovY);
    if (m_options.jumpTo.size() >= 2) {  // --goto LAT,LON[,ALTITUDE]
        m_pose.where = {m_options.jumpTo[0], m_options.jumpTo[1],
                        m_options.jumpTo.size() > 2 ? m_options.jumpTo[2] : kDefaultAltitudeM};
        m_pose.pitchDeg = kFlyToPitchDeg;
    }
    settings.jumpX = m_pose.where.latitudeDeg;
    settings.jumpY = m_pose.where.longitudeDeg;
    settings.jumpHeightM = kDefaultAltitudeM;
    // A globe has no fog by default: the atmosphere is not modelled, and a fog tuned to a
    // DEM's extent would hide the planet from orbit.
    settings.fog = false;
    settings.fogDensityPerM = 0.0f;
    runtime::placeOnGlobe(camera, m_pose);
    return {};
}

void GlobeControls::home(runtime::Camera& camera) {
    m_pose = overData(m_session->manifest(), camera.fovY);
    runtime::placeOnGlobe(camera, m_pose);
}

std::optional<globe::Geodetic> GlobeControls::groundUnderPixel(const runtime::Camera& camera,
                                                               double xPx, double yPx) const {
    const glm::dmat4 inverse = glm::inverse(camera.relativeViewProjection());
    const int x = static_cast<int>(xPx);
    const int y = camera.viewportHeight - 1 - static_cast<int>(yPx);  // rows bottom-up
    const glm::dvec3 direction = glm::normalize(runtime::unprojectPixel(
        inverse, camera.viewportWidth, camera.viewportHeight, x, y, 0.5));
    const glm::dvec3 radii(globe::Wgs84::kEquatorialRadius, globe::Wgs84::kEquatorialRadius,
                           globe::Wgs84::kPolarRadius);
    const glm::dvec3 o = camera.position / radii, d = direction / radii;
    const double a = glm::dot(d, d), b = glm::dot(o, d), c = glm::dot(o, o) - 1.0;
    const double discriminant = b * b - a * c;
    if (discriminant < 0.0 || c < 0.0) return std::nullopt;
    const double t = (-b - std::sqrt(discriminant)) / a;
    if (t <= 0.0) return std::nullopt;
    return globe::Wgs84::toGeodetic(camera.position + t * direction);
}

double GlobeControls::floorUnderCamera(const runtime::Camera& camera) const {
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
    return runtime::residentGroundHeight(camera.position, streamer.layout(), lookup);
}

void GlobeControls::move(runtime::Camera& camera, const runtime::CameraInput& held,
                         const WindowInput& window, double, double dtS) {
    runtime::GlobeControlInput control;
    control.held = held;
    control.lookAround = control.held.boost && window.dragging();
    if (control.lookAround) control.held.boost = false;
    control.focalPx = 0.5 * double(camera.viewportHeight) / std::tan(0.5 * camera.fovY);
    if (control.held.wheelSteps != 0.0) {
        const PixelPosition cursor = window.cursorInFramebufferPixels();
        control.zoomToward = groundUnderPixel(camera, cursor.x, cursor.y);
    }
    const double floor = m_keepAboveGround ? floorUnderCamera(camera)
                                           : -std::numeric_limits<double>::infinity();
    m_controller.update(m_pose, control, dtS, floor);
    runtime::placeOnGlobe(camera, m_pose);
}

void GlobeControls::placed(runtime::Camera& camera) { m_pose = runtime::globePoseOf(camera); }

std::string GlobeControls::orbitAt(runtime::Camera&, const SceneTarget&, double, double, bool) {
    return "on a globe, drag spins the Earth (orbiting a point is for planar pyramids)";
}

std::string GlobeControls::toggleOrbit(runtime::Camera& camera, const SceneTarget& scene) {
    return orbitAt(camera, scene, 0.0, 0.0, true);
}

std::string GlobeControls::jump(runtime::Camera& camera, const ViewerSettings& settings,
                                double) {
    m_pose.where = {std::clamp(settings.jumpX, -90.0, 90.0), settings.jumpY,
                    std::max(settings.jumpHeightM, 1.0)};
    m_pose.pitchDeg = kFlyToPitchDeg;
    runtime::placeOnGlobe(camera, m_pose);
    return fmt::format("flew to {:.5f}°, {:.5f}°, {:.0f} m above WGS84", m_pose.where.latitudeDeg,
                       m_pose.where.longitudeDeg, m_pose.where.height);
}

void GlobeControls::apply(const ViewerSettings& settings) {
    m_keepAboveGround = settings.keepAboveGround;
}

void GlobeControls::drawCameraLines(const runtime::Camera&, bool playing) const {
    using namespace overlay;
    text(fmt::format("{:.5f}°, {:.5f}°, {:.0f} m above WGS84", m_pose.where.latitudeDeg,
                     m_pose.where.longitudeDeg, m_pose.where.height));
    text(fmt::format("heading {:.1f}°, pitch {:.1f}°", m_pose.headingDeg, m_pose.pitchDeg));
    const runtime::LodUpdateStats& lod = m_session->lodStats();
    dimText(fmt::format("{} virtual, {} bare patches, {} behind the horizon", lod.drawnVirtual,
                        lod.drawnBare, lod.horizonCulled));
    if (playing) dimText("playing the camera path (any flight key takes over)");
}

void GlobeControls::drawCameraSection(const runtime::Camera& camera, ViewerSettings& settings,
                                      OverlayRequests& out, bool focusFields) {
    using namespace overlay;
    if (button("go to the data (H)")) out.actions.push_back(ViewerAction::Home);
    ImGui::SameLine();
    if (button("whole Earth")) {
        m_pose = runtime::GlobeController::wholeEarth(m_pose.where.latitudeDeg,
                                                      m_pose.where.longitudeDeg);
    }
    (void)camera;
    const io::ManifestGlobe& g = *m_session->manifest().globe;
    dimText(fmt::format("data {:.3f}° .. {:.3f}° N, {:.3f}° .. {:.3f}° E", g.south, g.north,
                        g.west, g.east));
    dimText("drag: spin · Shift-drag: look · wheel: zoom to the cursor · WASD/QE: fly");
    if (focusFields) {
        ImGui::SetWindowFocus();
        ImGui::SetKeyboardFocusHere();
    }
    bool go = jumpField("latitude", &settings.jumpX, "%.5f");
    go |= jumpField("longitude", &settings.jumpY, "%.5f");
    go |= jumpField("m above WGS84", &settings.jumpHeightM, "%.0f");
    if (button("fly there") || go) out.jump = true;
}

nlohmann::json GlobeControls::cameraJson(const runtime::Camera&) const {
    return {{"latitude", m_pose.where.latitudeDeg},
            {"longitude", m_pose.where.longitudeDeg},
            {"altitude_m", m_pose.where.height},
            {"heading_deg", m_pose.headingDeg},
            {"pitch_deg", m_pose.pitchDeg}};
}

std::string GlobeControls::rootFaultText(const std::string& fault) const {
    return "a cube face's data cannot be drawn, its root patch failed: " + fault;
}

std::array<float, 3> GlobeControls::skyColor() const { return kSpace; }

}  // namespace terrain::view
