// PlaneControls: terrain-view's ViewControls over a planar pyramid. Mouse-look and WASD flight
// with a speed that follows the height, orbiting a picked point, jumps to projected
// coordinates that follow the ground heights as finer tiles arrive, and the camera kept above
// the ground the streamer has (DESIGN.md, "The viewer").
#include "ViewControls.h"
#include "ViewerOptions.h"

#include "OverlayWidgets.h"
#include "SceneTarget.h"
#include "ViewerOverlay.h"

#include "terrain/runtime/CameraController.h"
#include "terrain/runtime/CameraPath.h"
#include "terrain/runtime/GroundHeight.h"
#include "terrain/runtime/PlaneSurface.h"
#include "terrain/runtime/TerrainGeometry.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>

namespace terrain::view {
namespace {

constexpr double kLandingS = 5.0;  // how long a jump follows the arriving ground heights

std::string crsText(const io::Georeference& georeference) {
    std::string text = io::crsKindName(georeference.crsKind);
    if (georeference.epsg != 0) text += fmt::format(", EPSG:{}", georeference.epsg);
    return text;
}

class PlaneControls final : public ViewControls {
public:
    PlaneControls(const runtime::TerrainSession& session, const ViewerOptions& options)
        : m_options(options),
          m_crsText(crsText(session.manifest().georeference)),
          m_home(runtime::CameraPath::defaultFor(runtime::planeGeometry(session.surface()))) {
        attach(session);
        m_ground = [this](double x, double y) { return groundAt(x, y); };
    }

    void attach(const runtime::TerrainSession& session) override { m_session = &session; }

    /// The end of the default flight's path over the DEM; --orbit orbits the point it looks
    /// at, --goto jumps to X,Y at a height above the ground.
    std::string start(runtime::Camera& camera, ViewerSettings& settings) override {
        const runtime::TerrainGeometry& g = geometry();
        camera.nearPlane = 0.5;
        const glm::dvec2 extent = g.demSize();
        const glm::dvec2 centre = g.worldAtFraction(0.5, 0.5);
        settings.jumpX = centre.x;
        settings.jumpY = centre.y;
        settings.jumpHeightM = std::clamp(0.02 * std::max(extent.x, extent.y), 100.0, 5000.0);
        home(camera);
        if (m_options.orbit) {
            // The point the home view looks at (its centre ray meets the lowest ground there).
            const glm::dvec3 pivot =
                runtime::pointOnPlaneOrAhead(camera.position, camera.forward(), g.minHeight(),
                                             4.0 * std::max(extent.x, extent.y));
            m_controller.orbit(camera, pivot);
        }
        if (m_options.jumpTo.empty()) return {};
        settings.jumpX = m_options.jumpTo[0];
        settings.jumpY = m_options.jumpTo[1];
        if (m_options.jumpTo.size() > 2) settings.jumpHeightM = m_options.jumpTo[2];
        return jump(camera, settings, 0.0);  // in orbit mode the point becomes the pivot
    }

    void home(runtime::Camera& camera) override {
        m_home.apply(m_home.endS(), camera);
        m_controller.fly();
    }

    /// Flight or orbit (CameraController) above the conservative ground; for a few seconds
    /// after a jump, the landing follows the finer ground heights as they arrive.
    void move(runtime::Camera& camera, const runtime::CameraInput& held, const WindowInput&,
              double timeS, double dtS) override {
        if (m_landing) {
            if (held.any() || timeS > m_landing->untilS) {
                m_landing.reset();
            } else if (const double ground = groundAt(m_landing->x, m_landing->y);
                       ground < m_landing->groundM) {
                m_controller.jumpTo(camera, m_landing->x, m_landing->y, m_landing->heightM,
                                    m_ground);
                m_landing->groundM = ground;
            }
        }
        m_controller.update(camera, held, dtS, m_ground);
    }

    /// Flies on from the path's camera (an orbit would re-aim it).
    void placed(runtime::Camera& camera) override {
        // A path flies: an orbit would re-aim the camera it placed at the pivot.
        m_landing.reset();
        m_controller.fly();
        m_controller.cameraMovedExternally(camera);
    }

    /// The pivot: the depth buffer's point under the pixel, or one ahead on the ground.
    std::string orbitAt(runtime::Camera& camera, const SceneTarget& scene, double xPx, double yPx,
                        bool fallbackAhead) override {
        const std::optional<double> depth =
            scene.depthAt(static_cast<int>(xPx), static_cast<int>(yPx));
        glm::dvec3 pivot;
        if (depth) {
            pivot = runtime::pointAtDepth(camera, xPx, yPx, *depth);
        } else if (fallbackAhead) {
            // Sky at the centre: orbit a point ahead on the ground's level.
            const double ground = groundAt(camera.position.x, camera.position.y);
            const double height = std::max(camera.position.z - ground, 100.0);
            pivot = runtime::pointOnPlaneOrAhead(
                camera.position, runtime::viewRay(camera, xPx, yPx), ground, 4.0 * height);
        } else {
            return "no terrain under the cursor to orbit";
        }
        m_landing.reset();
        m_controller.orbit(camera, pivot);
        return {};
    }

    std::string toggleOrbit(runtime::Camera& camera, const SceneTarget& scene) override {
        if (m_controller.mode() == runtime::CameraMode::Orbit) {
            m_controller.fly();
            return {};
        }
        return orbitAt(camera, scene, 0.5 * scene.width(), 0.5 * scene.height(), true);
    }

    /// To world x, y (the pyramid's CRS) at a height above the ground there.
    std::string jump(runtime::Camera& camera, const ViewerSettings& settings,
                     double timeS) override {
        m_controller.jumpTo(camera, settings.jumpX, settings.jumpY, settings.jumpHeightM, m_ground);
        const glm::dvec2 sample = geometry().sampleOfWorld(settings.jumpX, settings.jumpY);
        const io::PyramidLayout& layout = geometry().layout();
        const bool inside = sample.x >= 0.0 && sample.y >= 0.0 &&
                            sample.x <= static_cast<double>(layout.rasterWidth() - 1) &&
                            sample.y <= static_cast<double>(layout.rasterHeight() - 1);
        m_landing = LandingJump{settings.jumpX, settings.jumpY, settings.jumpHeightM,
                                groundAt(settings.jumpX, settings.jumpY), timeS + kLandingS};
        return fmt::format("jumped to x {:.1f}, y {:.1f}{}", settings.jumpX, settings.jumpY,
                           inside ? "" : " (outside the DEM)");
    }

    void apply(const ViewerSettings& settings) override {
        runtime::CameraControllerOptions controls = m_controller.options();
        controls.keepAboveGround = settings.keepAboveGround;
        m_controller.setOptions(controls);
    }

    /// Mode, position, heading, pitch, height above ground, speed or orbit distance.
    void drawCameraLines(const runtime::Camera& c, bool playing) const override {
        using namespace overlay;
        const bool orbiting = m_controller.mode() == runtime::CameraMode::Orbit;
        text(fmt::format("{} · x {:.0f}  y {:.0f}  z {:.0f} m", orbiting ? "orbit" : "fly",
                         c.position.x, c.position.y, c.position.z));
        text(fmt::format("heading {:.0f}°  pitch {:.0f}° · {:.0f} m above ground",
                         std::fmod(degrees(c.yaw) + 360.0, 360.0), degrees(c.pitch),
                         c.position.z - groundAt(c.position.x, c.position.y)));
        if (playing) {
            dimText("playing the camera path (any flight key takes over)");
        } else if (orbiting) {
            dimText(fmt::format("{:.0f} m from the pivot", m_controller.orbitDistance()));
        } else {
            dimText(fmt::format("speed {:.0f} m/s (wheel: × {:.2f})", m_controller.speedMps(),
                                m_controller.speedScale()));
        }
    }

    /// Orbit/fly, the whole DEM, the DEM's extent and heights, x/y/height fields.
    void drawCameraSection(const runtime::Camera&, ViewerSettings& settings, OverlayRequests& out,
                           bool focusFields) override {
        using namespace overlay;
        if (m_controller.mode() == runtime::CameraMode::Orbit) {
            const glm::dvec3 pivot = m_controller.pivot();
            text(fmt::format("orbiting x {:.0f} y {:.0f} z {:.0f}", pivot.x, pivot.y, pivot.z));
            if (button("fly (O)")) out.actions.push_back(ViewerAction::ToggleOrbit);
        } else {
            text(fmt::format("flying, speed × {:.2f} (wheel)", m_controller.speedScale()));
            if (button("orbit the centre (O)")) out.actions.push_back(ViewerAction::ToggleOrbit);
        }
        ImGui::SameLine();
        if (button("whole DEM (H)")) out.actions.push_back(ViewerAction::Home);

        const runtime::TerrainGeometry& g = geometry();
        const glm::dvec2 northWest = g.worldAtFraction(0.0, 0.0);
        const glm::dvec2 southEast = g.worldAtFraction(1.0, 1.0);
        const glm::dvec2 lo{std::min(northWest.x, southEast.x), std::min(northWest.y, southEast.y)};
        const glm::dvec2 hi{std::max(northWest.x, southEast.x), std::max(northWest.y, southEast.y)};
        dimText(fmt::format("DEM x {:.0f} .. {:.0f}, y {:.0f} .. {:.0f}", lo.x, hi.x, lo.y, hi.y));
        dimText(fmt::format("heights {:.0f} .. {:.0f} m · {}", g.minHeight(), g.maxHeight(),
                            m_crsText));
        if (focusFields) {
            ImGui::SetWindowFocus();  // so Tab moves between the fields
            ImGui::SetKeyboardFocusHere();
        }
        // Edits apply as typed (Tab keeps them); Enter in any of the fields jumps.
        bool go = jumpField("x (east)", &settings.jumpX, "%.1f");
        go |= jumpField("y (north)", &settings.jumpY, "%.1f");
        go |= jumpField("m above ground", &settings.jumpHeightM, "%.0f");
        if (button("jump") || go) out.jump = true;
        if (settings.jumpX < lo.x || settings.jumpX > hi.x || settings.jumpY < lo.y ||
            settings.jumpY > hi.y) {
            ImGui::SameLine();
            ImGui::TextColored(kWarn, "outside the DEM");
        }
    }

    /// mode, position_m, yaw_deg, pitch_deg.
    nlohmann::json cameraJson(const runtime::Camera& camera) const override {
        return {{"mode", m_controller.mode() == runtime::CameraMode::Orbit ? "orbit" : "fly"},
                {"position_m", {camera.position.x, camera.position.y, camera.position.z}},
                {"yaw_deg", overlay::degrees(camera.yaw)},
                {"pitch_deg", overlay::degrees(camera.pitch)}};
    }



private:
    const runtime::TerrainGeometry& geometry() const {
        return runtime::planeGeometry(m_session->surface());
    }

    /// The conservative ground height under (x, y): the finest resident tile's, so a jump
    /// or the floor never puts the camera under terrain that is drawn.
    double groundAt(double x, double y) const {
        return runtime::conservativeGroundHeight(m_session->streamer(), geometry(), x, y);
    }

    ViewerOptions m_options;
    const runtime::TerrainSession* m_session = nullptr;
    std::string m_crsText;
    runtime::CameraPath m_home;
    runtime::CameraController m_controller;
    runtime::GroundHeightFn m_ground;

    // A jump lands over a conservative ground height, which drops as finer tiles of the
    // target arrive: for a few seconds (until the user moves) the jump is redone on it.
    struct LandingJump {
        double x = 0.0;
        double y = 0.0;
        double heightM = 0.0;
        double groundM = 0.0;
        double untilS = 0.0;
    };
    std::optional<LandingJump> m_landing;
};

}  // namespace

std::unique_ptr<ViewControls> makePlaneControls(const runtime::TerrainSession& session,
                                                const ViewerOptions& options) {
    return std::make_unique<PlaneControls>(session, options);
}

}  // namespace terrain::view
