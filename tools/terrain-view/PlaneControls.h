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
