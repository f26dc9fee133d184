// GlobeControls: terrain-view over a globe pyramid (DESIGN.md, "The globe"), with the controls
// a user of a virtual globe expects: drag to spin the globe, the wheel zooming toward the
// cursor, Shift-drag to look around, WASD and Q/E flight whose speed follows the height,
// "go to the data", "the whole Earth", fly to a latitude, longitude and altitude; the camera
// stays above the ground the finest resident data draws under it.
#pragma once

#include "ViewControls.h"
#include "ViewerOptions.h"

#include "terrain/globe/Wgs84.h"
#include "terrain/runtime/GlobeCamera.h"
#include "terrain/runtime/GlobeController.h"

#include <optional>
#include <string>

namespace terrain::view {

class GlobeControls final : public ViewControls {
public:
    GlobeControls(const runtime::TerrainSession& session, const ViewerOptions& options);

    void attach(const runtime::TerrainSession& session) override;
    /// Over the data's extent, or at --goto's latitude, longitude and altitude looking 30°
    /// down; no fog (a fog scaled to a DEM would hide the planet from orbit).
    std::string start(runtime::Camera& camera, ViewerSettings& settings) override;
    void home(runtime::Camera& camera) override;
    /// GlobeController: a drag spins the globe (Shift-drag looks around), the wheel zooms
    /// toward the ellipsoid under the cursor; the floor is the drawn ground under the camera.
    void move(runtime::Camera& camera, const runtime::CameraInput& held,
              const WindowInput& window, double timeS, double dtS) override;
    /// Takes the path camera's latitude, longitude, altitude, heading and pitch.
    void placed(runtime::Camera& camera) override;
    /// None on a globe: says that a drag spins the Earth.
    std::string orbitAt(runtime::Camera& camera, const SceneTarget& scene, double xPx, double yPx,
                        bool fallbackAhead) override;
    std::string toggleOrbit(runtime::Camera& camera, const SceneTarget& scene) override;
    /// To a latitude, longitude and altitude above WGS84, looking 30° down.
    std::string jump(runtime::Camera& camera, const ViewerSettings& settings,
                     double timeS) override;
    void apply(const ViewerSettings& settings) override;
    /// Latitude, longitude, altitude, heading, pitch; virtual, bare and horizon-culled patches.
    void drawCameraLines(const runtime::Camera& camera, bool playing) const override;
    /// Go to the data, the whole Earth, the data's extent, latitude/longitude/altitude fields.
    void drawCameraSection(const runtime::Camera& camera, ViewerSettings& settings,
                           OverlayRequests& out, bool focusFields) override;
    /// latitude, longitude, altitude_m, heading_deg, pitch_deg.
    nlohmann::json cameraJson(const runtime::Camera& camera) const override;
    std::string rootFaultText(const std::string& fault) const override;
    std::array<float, 3> skyColor() const override;

private:
    /// Where the ray through a framebuffer pixel (rows top-down) meets the ellipsoid.
    std::optional<globe::Geodetic> groundUnderPixel(const runtime::Camera& camera, double xPx,
                                                    double yPx) const;
    /// The ground the finest resident data draws under the camera.
    double floorUnderCamera(const runtime::Camera& camera) const;

    ViewerOptions m_options;
    const runtime::TerrainSession* m_session = nullptr;
    runtime::GlobePose m_pose;
    runtime::GlobeController m_controller;
    bool m_keepAboveGround = true;
};

}  // namespace terrain::view
