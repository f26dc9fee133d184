// PlaneControls: terrain-view over a planar pyramid. Mouse-look and WASD flight with a speed
// that follows the height, orbiting a picked point, jumps to projected coordinates that
// follow the ground heights as finer tiles arrive, and the camera kept above the ground the
// streamer has (DESIGN.md, "The viewer").
#pragma once

#include "ViewControls.h"
#include "ViewerOptions.h"

#include "terrain/runtime/CameraController.h"
#include "terrain/runtime/CameraPath.h"
#include "terrain/runtime/TerrainGeometry.h"

#include <optional>
#include <string>

namespace terrain::view {

class PlaneControls final : public ViewControls {
public:
    PlaneControls(const runtime::TerrainSession& session, const ViewerOptions& options);

    void attach(const runtime::TerrainSession& session) override;
    /// The end of the default flight's path over the DEM; --orbit orbits the point it looks
    /// at, --goto jumps to X,Y at a height above the ground; fog scaled to the DEM.
    std::string start(runtime::Camera& camera, ViewerSettings& settings) override;
    void home(runtime::Camera& camera) override;
    /// Flight or orbit (CameraController) above the conservative ground; for a few seconds
    /// after a jump, the landing follows the finer ground heights as they arrive.
    void move(runtime::Camera& camera, const runtime::CameraInput& held,
              const WindowInput& window, double timeS, double dtS) override;
    /// Flies on from the path's camera (an orbit would re-aim it).
    void placed(runtime::Camera& camera) override;
    /// The pivot: the depth buffer's point under the pixel, or one ahead on the ground.
    std::string orbitAt(runtime::Camera& camera, const SceneTarget& scene, double xPx, double yPx,
                        bool fallbackAhead) override;
    std::string toggleOrbit(runtime::Camera& camera, const SceneTarget& scene) override;
    /// To world x, y (the pyramid's CRS) at a height above the ground there.
    std::string jump(runtime::Camera& camera, const ViewerSettings& settings,
                     double timeS) override;
    void apply(const ViewerSettings& settings) override;
    /// Mode, position, heading, pitch, height above ground, speed or orbit distance.
    void drawCameraLines(const runtime::Camera& camera, bool playing) const override;
    /// Orbit/fly, the whole DEM, the DEM's extent and heights, x/y/height fields.
    void drawCameraSection(const runtime::Camera& camera, ViewerSettings& settings,
                           OverlayRequests& out, bool focusFields) override;
    /// mode, position_m, yaw_deg, pitch_deg.
    nlohmann::json cameraJson(const runtime::Camera& camera) const override;
    std::string rootFaultText(const std::string& fault) const override;
    std::array<float, 3> skyColor() const override;

private:
    /// The conservative ground height under (x, y): the finest resident tile's, so a jump
    /// or the floor never puts the camera under terrain that is drawn.
    double groundAt(double x, double y) const;
    const runtime::TerrainGeometry& geometry() const;

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

}  // namespace terrain::view
