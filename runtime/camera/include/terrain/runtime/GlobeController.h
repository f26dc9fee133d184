// GlobeController: the viewer's camera controls on a globe, without a window system (as
// CameraController on the plane). Dragging spins the globe under the camera so the ground
// follows the cursor; Shift-dragging looks around (heading and pitch); the wheel zooms toward
// the ground under the cursor; W/S/A/D fly over the ground and Q/E descend and climb, at a
// speed that follows the height (one height per second: slow near the ground, fast from
// orbit). "Go to the data" and "the whole Earth" are poses it computes.
#pragma once

#include "terrain/runtime/CameraController.h"
#include "terrain/runtime/GlobeCamera.h"

#include <optional>

namespace terrain::runtime {

struct GlobeControllerOptions {
    double lookRadiansPerPx = 0.003;
    double wheelZoomStep = 0.85;  ///< one wheel step multiplies the height by this
    double climbPerS = 1.0;       ///< Q/E: height × e^(∓climbPerS · dt)
    double speedPerHeightPerS = 1.0;
    double minSpeedMps = 5.0;
    double maxSpeedMps = 3.0e6;
    double boostFactor = 5.0;
    double slowFactor = 0.2;
    double minClearanceM = 1.0;  ///< above the floor the caller gives
    double maxHeightM = 1.0e8;
};

struct GlobeControlInput {
    CameraInput held;         ///< keys held, mouse travel while dragging, wheel steps
    bool lookAround = false;  ///< the drag turns the camera instead of spinning the globe
    double focalPx = 1000.0;  ///< pixels per radian at the centre: the drag's scale
    /// Where the wheel zooms: the ground point under the cursor, if the cursor is on the globe.
    std::optional<globe::Geodetic> zoomToward;
};

class GlobeController {
public:
    explicit GlobeController(const GlobeControllerOptions& options = {}) : m_options(options) {}

    /// Moves `pose` by `input` over `dtS` seconds, keeping it minClearanceM above `floorM`
    /// (a height at or above the ground under the camera).
    void update(GlobePose& pose, const GlobeControlInput& input, double dtS, double floorM) const;

    /// Straight down on the centre of [west, south, east, north] (degrees, west > east across
    /// the antimeridian) from where it just fills the view: "go to the data".
    static GlobePose overExtent(double west, double south, double east, double north, double fovY);
    /// The whole Earth from 20,000 km, over a latitude and longitude.
    static GlobePose wholeEarth(double latitudeDeg, double longitudeDeg);

    /// Moves a pose `forwardM` along its heading and `rightM` to its right over the ground,
    /// the height kept (a pole is clamped 1e-4° short, so the heading stays defined).
    static void moveOverGround(GlobePose& pose, double forwardM, double rightM);

    const GlobeControllerOptions& options() const { return m_options; }

private:
    GlobeControllerOptions m_options;
};

}  // namespace terrain::runtime
