// GlobeControls: terrain-view's ViewControls over a globe pyramid (DESIGN.md, "The globe"),
// the controls a user of a virtual globe expects: drag to spin the globe, the wheel zooming
// toward the cursor, Shift-drag to look around, WASD and Q/E flight whose speed follows the
// height, "go to the data", "the whole Earth", fly to a latitude, longitude and altitude; the
// camera stays above the ground the finest resident data draws under it.
#include "ViewControls.h"
#include "ViewerOptions.h"

#include "OverlayWidgets.h"
#include "ViewerOverlay.h"

#include "terrain/globe/Wgs84.h"
#include "terrain/pyramid/GlobeLayout.h"
#include "terrain/runtime/GlobeCamera.h"
#include "terrain/runtime/GlobeCameraPath.h"
#include "terrain/runtime/GlobeController.h"
#include "terrain/runtime/GlobeDrawnGround.h"
#include "terrain/runtime/ScreenProjection.h"

#include <fmt/core.h>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <string>

namespace terrain::view {
namespace {

constexpr double kDegree = std::numbers::pi / 180.0;
constexpr double kFlyToPitchDeg = -30.0;
constexpr double kDefaultAltitudeM = 10000.0;

runtime::GlobePose overData(const io::PyramidManifest& manifest, double fovY) {
    const io::ManifestGlobe& g = *manifest.globe;
    return runtime::GlobeController::overExtent(g.west, g.south, g.east, g.north, fovY);
}

class GlobeControls final : public ViewControls {
public:
    GlobeControls(const runtime::TerrainSession& session, const ViewerOptions& options)
        : m_options(options) {
        attach(session);
    }

    void attach(const runtime::TerrainSession& session) override { m_session = &session; }

    /// Over the data's extent, or at --goto's latitude, longitude and altitude looking 30°
    /// down.
    std::string start(runtime::Camera& camera, ViewerSettings& settings) override {
        camera.fovY = runtime::GlobeCameraPath::kDefaultFovYDegrees * kDegree;
        m_pose = overData(m_session->manifest(), camera.fovY);
        if (m_options.jumpTo.size() >= 2) {  // --goto LAT,LON[,ALTITUDE]
            m_pose.where = {m_options.jumpTo[0], m_options.jumpTo[1],
                            m_options.jumpTo.size() > 2 ? m_options.jumpTo[2] : kDefaultAltitudeM};
            m_pose.pitchDeg = kFlyToPitchDeg;
        }
        settings.jumpX = m_pose.where.latitudeDeg;
        settings.jumpY = m_pose.where.longitudeDeg;
        settings.jumpHeightM = kDefaultAltitudeM;
        runtime::placeOnGlobe(camera, m_pose);
        return {};
    }

    void home(runtime::Camera& camera) override {
        m_pose = overData(m_session->manifest(), camera.fovY);
        runtime::placeOnGlobe(camera, m_pose);
    }

    /// GlobeController: a drag spins the globe (Shift-drag looks around), the wheel zooms
    /// toward the ellipsoid under the cursor; the floor is the drawn ground under the camera.
    void move(runtime::Camera& camera, const runtime::CameraInput& held, const WindowInput& window,
              double, double dtS) override {
        runtime::GlobeControlInput control;
        control.held = held;
        control.lookAround = control.held.boost && window.dragging();
        if (control.lookAround) control.held.boost = false;
        control.focalPx = 0.5 * double(camera.viewportHeight) / std::tan(0.5 * camera.fovY);
        if (control.held.wheelSteps != 0.0) {
            const PixelPosition cursor = window.cursorInFramebufferPixels();
            control.zoomToward = groundUnderPixel(camera, cursor.x, cursor.y);
        }
        const double floor =
            m_keepAboveGround ? floorUnderCamera(camera) : -std::numeric_limits<double>::infinity();
        m_controller.update(m_pose, control, dtS, floor);
        runtime::placeOnGlobe(camera, m_pose);
    }

    /// Takes the path camera's latitude, longitude, altitude, heading and pitch.
    void placed(runtime::Camera& camera) override { m_pose = runtime::globePoseOf(camera); }

    /// None on a globe: says that a drag spins the Earth.
    std::string orbitAt(runtime::Camera&, const SceneTarget&, double, double, bool) override {
        return "on a globe, drag spins the Earth (orbiting a point is for planar pyramids)";
    }

    std::string toggleOrbit(runtime::Camera& camera, const SceneTarget& scene) override {
        return orbitAt(camera, scene, 0.0, 0.0, true);
    }

    /// To a latitude, longitude and altitude above WGS84, looking 30° down.
    std::string jump(runtime::Camera& camera, const ViewerSettings& settings, double) override {
        m_pose.where = {std::clamp(settings.jumpX, -90.0, 90.0), settings.jumpY,
                        std::max(settings.jumpHeightM, 1.0)};
        m_pose.pitchDeg = kFlyToPitchDeg;
        runtime::placeOnGlobe(camera, m_pose);
        return fmt::format("flew to {:.5f}°, {:.5f}°, {:.0f} m above WGS84",
                           m_pose.where.latitudeDeg, m_pose.where.longitudeDeg,
                           m_pose.where.height);
    }

    void apply(const ViewerSettings& settings) override {
        m_keepAboveGround = settings.keepAboveGround;
    }

    /// Latitude, longitude, altitude, heading, pitch; virtual, bare and horizon-culled patches.
    void drawCameraLines(const runtime::Camera&, bool playing) const override {
        using namespace overlay;
        text(fmt::format("{:.5f}°, {:.5f}°, {:.0f} m above WGS84", m_pose.where.latitudeDeg,
                         m_pose.where.longitudeDeg, m_pose.where.height));
        text(fmt::format("heading {:.1f}°, pitch {:.1f}°", m_pose.headingDeg, m_pose.pitchDeg));
        const runtime::LodUpdateStats& lod = m_session->lodStats();
        dimText(fmt::format("{} virtual, {} bare patches, {} behind the horizon", lod.drawnVirtual,
                            lod.drawnBare, lod.horizonCulled));
        if (playing) dimText("playing the camera path (any flight key takes over)");
    }

    /// Go to the data, the whole Earth, the data's extent, latitude/longitude/altitude fields.
    void drawCameraSection(const runtime::Camera& /*camera*/, ViewerSettings& settings,
                           OverlayRequests& out, bool focusFields) override {
        using namespace overlay;
        if (button("go to the data (H)")) out.actions.push_back(ViewerAction::Home);
        ImGui::SameLine();
        if (button("whole Earth")) {
            m_pose = runtime::GlobeController::wholeEarth(m_pose.where.latitudeDeg,
                                                          m_pose.where.longitudeDeg);
        }
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

    /// latitude, longitude, altitude_m, heading_deg, pitch_deg.
    nlohmann::json cameraJson(const runtime::Camera&) const override {
        return {{"latitude", m_pose.where.latitudeDeg},
                {"longitude", m_pose.where.longitudeDeg},
                {"altitude_m", m_pose.where.height},
                {"heading_deg", m_pose.headingDeg},
                {"pitch_deg", m_pose.pitchDeg}};
    }



private:
    /// Where the ray through a framebuffer pixel (rows top-down) meets the ellipsoid.
    std::optional<globe::Geodetic> groundUnderPixel(const runtime::Camera& camera, double xPx,
                                                    double yPx) const {
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

    /// The ground the finest resident data draws under the camera.
    double floorUnderCamera(const runtime::Camera& camera) const {
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
                },
            .nativeTileUnder =
                [this](const glm::dvec3& up, int level) {
                    return m_session->surface().nativeTileUnder(up, level);
                },
            .cachedNativeTile =
                [&streamer](const io::PatchId& id) { return streamer.cpuCache().peek(id); }};
        return runtime::residentGroundHeight(camera.position, streamer.layout(), lookup);
    }

    ViewerOptions m_options;
    const runtime::TerrainSession* m_session = nullptr;
    runtime::GlobePose m_pose;
    runtime::GlobeController m_controller;
    bool m_keepAboveGround = true;
};

}  // namespace

std::unique_ptr<ViewControls> makeGlobeControls(const runtime::TerrainSession& session,
                                                const ViewerOptions& options) {
    return std::make_unique<GlobeControls>(session, options);
}

}  // namespace terrain::view
