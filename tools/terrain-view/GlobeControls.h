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
    std::string start(runtime::Camera& camera, ViewerSettings& settings) override;
    void home(runtime::Camera& camera) override;
    void move(runtime::Camera& camera, const runtime::CameraInput& held,
              const WindowInput& window, double timeS, double dtS) override;
    void placed(runtime::Camera& camera) override;
    std::string orbitAt(runtime::Camera& camera, const SceneTarget& scene, double xPx, double yPx,
                        bool fallbackAhead) override;
    std::string toggleOrbit(runtime::Camera& camera, const SceneTarget& scene) override;
    std::string jump(runtime::Camera& camera, const ViewerSettings& settings,
                     double timeS) override;
    void apply(const ViewerSettings& settings) override;
    void drawCameraLines(const runtime::Camera& camera, bool playing) const override;
    void drawCameraSection(const runtime::Camera& camera, ViewerSettings& settings,
                           OverlayRequests& out, bool focusFields) override;
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
