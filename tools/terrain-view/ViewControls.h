// ViewControls: what terrain-view does differently on each kind of surface, behind the one
// Viewer (window, session, overlay, paths, logs, screenshots). On the plane the user flies or
// orbits over a DEM in its projected metres (PlaneControls); on the globe the user spins the
// Earth, zooms toward the cursor and flies over the ellipsoid by latitude and longitude
// (GlobeControls). Everything else in the viewer is the same code for both; what every
// program does per surface (the sky and fog, what a failed root means, the path format) is
// tools/common's SurfaceKit. Each
// implementation lives in its .cpp file, made by ViewControls::create.
#pragma once

#include "ViewerSettings.h"
#include "WindowInput.h"

#include "terrain/runtime/Camera.h"
#include "terrain/runtime/TerrainSession.h"

#include <nlohmann/json.hpp>

#include <memory>
#include <string>

namespace terrain::view {

class SceneTarget;
struct OverlayRequests;
struct ViewerOptions;

/// Render thread only.
class ViewControls {
public:
    /// The controls for the surface of `session`'s pyramid.
    static std::unique_ptr<ViewControls> create(const runtime::TerrainSession& session,
                                                const ViewerOptions& options);
    virtual ~ViewControls() = default;

    /// Binds the controls to a (re-)opened session: the ground under the camera comes from
    /// its streamer.
    virtual void attach(const runtime::TerrainSession& session) = 0;

    /// The first view (the whole data, then --goto and --orbit) and the jump fields;
    /// returns a status line or "".
    virtual std::string start(runtime::Camera& camera, ViewerSettings& settings) = 0;
    /// Back to the view of the whole data (H).
    virtual void home(runtime::Camera& camera) = 0;

    /// Moves the camera by this frame's input; `timeS` is the flight time.
    virtual void move(runtime::Camera& camera, const runtime::CameraInput& held,
                      const WindowInput& window, double timeS, double dtS) = 0;
    /// A camera path placed the camera: the controls continue from there.
    virtual void placed(runtime::Camera& camera) = 0;
    /// Orbit the point under the pixel (or, when `fallbackAhead`, one ahead); the status
    /// line says what happened.
    virtual std::string orbitAt(runtime::Camera& camera, const SceneTarget& scene, double xPx,
                                double yPx, bool fallbackAhead) = 0;
    /// O: orbit the centre of the view, or fly again.
    virtual std::string toggleOrbit(runtime::Camera& camera, const SceneTarget& scene) = 0;
    /// Jump to the settings' jump fields (the plane's x, y and height above ground; the
    /// globe's latitude, longitude and altitude); the status line says where.
    virtual std::string jump(runtime::Camera& camera, const ViewerSettings& settings,
                             double timeS) = 0;
    /// The settings the controls follow (keep above ground).
    virtual void apply(const ViewerSettings& settings) = 0;

    /// Overlay: the camera lines under the telemetry, and the "Camera and jump to" section
    /// (inside ImGui's frame).
    virtual void drawCameraLines(const runtime::Camera& camera, bool playing) const = 0;
    virtual void drawCameraSection(const runtime::Camera& camera, ViewerSettings& settings,
                                   OverlayRequests& out, bool focusFields) = 0;

    /// The "camera" object of the --json summary.
    virtual nlohmann::json cameraJson(const runtime::Camera& camera) const = 0;
};

/// The two implementations (PlaneControls.cpp, GlobeControls.cpp); create() picks one.
std::unique_ptr<ViewControls> makePlaneControls(const runtime::TerrainSession& session,
                                                const ViewerOptions& options);
std::unique_ptr<ViewControls> makeGlobeControls(const runtime::TerrainSession& session,
                                                const ViewerOptions& options);

}  // namespace terrain::view
