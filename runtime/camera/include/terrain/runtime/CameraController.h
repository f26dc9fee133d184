// CameraController: the viewer's camera controls without a window system — mouse-look and
// keyboard flight whose speed scales with the height above the ground, orbiting a point,
// jumps to world coordinates, and the screen-to-world picking an orbit pivot needs. A
// window layer turns its events into a CameraInput once a frame; tests drive it with
// synthetic input and time steps.
//
// Motion is frame-rate independent: mouse travel turns the camera by the same angle however
// it is split into frames, and key-driven motion is integrated in equal sub-steps of at most
// CameraControllerOptions::maxStepS, so one 1/10 s frame moves the camera as far as six
// 1/60 s frames (the speed depends on the height, which changes during a frame).
#pragma once

#include "terrain/runtime/Camera.h"

#include <glm/vec3.hpp>

#include <functional>

namespace terrain::runtime {

enum class CameraMode {
    Fly,    ///< WASD along the view, Q/E down/up, mouse turns the camera
    Orbit,  ///< mouse turns the camera around a pivot it keeps looking at
};

/// What the user held and did since the previous update.
struct CameraInput {
    // Keys held during the step (the viewer's W, S, A, D, Q, E, Shift, Ctrl).
    bool forward = false;
    bool back = false;
    bool left = false;
    bool right = false;
    bool down = false;   ///< fly: world down; orbit: closer to the pivot
    bool up = false;     ///< fly: world up; orbit: further from the pivot
    bool boost = false;  ///< speed × boostFactor
    bool slow = false;   ///< speed × slowFactor
    /// Mouse travel while looking (fly) or dragging (orbit), pixels since the previous
    /// update; x to the right, y down the screen. Moving the mouse down looks down.
    double lookDxPx = 0.0;
    double lookDyPx = 0.0;
    /// Wheel steps since the previous update, positive away from the user: fly faster, or
    /// orbit closer.
    double wheelSteps = 0.0;

    /// Whether any key that moves the camera is held (the viewer stops a playing path then).
    bool movementHeld() const { return forward || back || left || right || down || up; }
    /// Whether anything in this input would change the camera.
    bool any() const {
        return movementHeld() || lookDxPx != 0.0 || lookDyPx != 0.0 || wheelSteps != 0.0;
    }
};

struct CameraControllerOptions {
    double lookRadiansPerPx = 0.003;
    /// Fly speed at height h above the ground: h · speedPerHeightPerS m/s (one height per
    /// second: slow near the ground, fast from orbit), clamped to [minSpeedMps, maxSpeedMps]
    /// and then scaled by the wheel, boost and slow factors.
    double speedPerHeightPerS = 1.0;
    double minSpeedMps = 5.0;
    double maxSpeedMps = 2.0e5;
    double boostFactor = 5.0;
    double slowFactor = 0.2;
    double wheelSpeedStep = 1.25;  ///< fly: one wheel step multiplies the speed by this
    double wheelZoomStep = 0.85;   ///< orbit: one wheel step multiplies the distance by this
    double orbitZoomPerS = 1.0;    ///< orbit, Q/E: distance × e^(∓orbitZoomPerS · dt)
    double orbitPanPerS = 0.75;    ///< orbit, WASD: the pivot moves this × distance per second
    double orbitMinDistanceM = 1.0;
    double orbitMinElevation = 0.0175;  ///< radians (1°) the camera stays above its pivot
    /// Time constant of the velocity's approach to what the keys ask for (ease in and out),
    /// seconds; 0 follows the keys at once.
    double responseS = 0.1;
    /// Keep the camera clearanceM above the ground (the ground function is conservative: at
    /// or above the real ground, so this is a floor the camera never passes below).
    bool keepAboveGround = true;
    double clearanceM = 2.0;
    /// Longest integration sub-step, seconds; a frame is split into equal sub-steps.
    double maxStepS = 1.0 / 240.0;
    /// A longer frame (a hitch: a window drag, a slow disk) counts as this long, so the
    /// camera does not leap; below 1 / maxFrameS frames per second motion slows down.
    double maxFrameS = 0.25;
    /// Pitch of the view after jumpTo() in fly mode: ahead and down.
    double jumpPitch = -0.61;  // −35°
};

/// Ground height under a world x, y in metres (the viewer passes conservativeGroundHeight).
using GroundHeightFn = std::function<double(double x, double y)>;

/// Render thread (or any one thread); allocates nothing.
class CameraController {
public:
    explicit CameraController(const CameraControllerOptions& options = {});

    const CameraControllerOptions& options() const { return m_options; }
    void setOptions(const CameraControllerOptions& options) { m_options = options; }

    CameraMode mode() const { return m_mode; }
    /// Leaves orbit mode (the camera stays where it is) and stops any motion.
    void fly();
    /// Orbits `pivot`: the camera turns to look at it and keeps its distance (at least
    /// orbitMinDistanceM, and at least orbitMinElevation above it).
    void orbit(Camera& camera, const glm::dvec3& pivot);
    const glm::dvec3& pivot() const { return m_pivot; }
    double orbitDistance() const { return m_distance; }

    /// Advances the camera by `dtS` seconds of `input`. `ground` gives the height under a
    /// point, for the speed and the floor. dtS ≤ 0 applies only the mouse and the wheel. `ground`
    /// must be set.
    void update(Camera& camera, const CameraInput& input, double dtS, const GroundHeightFn& ground);

    /// Puts the camera at heightAboveGroundM over world (x, y) — for a projected pyramid the
    /// map's easting and northing — keeping its heading. Fly: looking ahead and down
    /// (jumpPitch). Orbit: the point on the ground becomes the pivot and the camera looks at
    /// it from that height. Stops any motion.
    void jumpTo(Camera& camera, double x, double y, double heightAboveGroundM,
                const GroundHeightFn& ground);

    /// Call when something else moved the camera (a path, a reset): forgets the velocity
    /// and, in orbit mode, re-aims at the pivot from where the camera now is.
    void cameraMovedExternally(Camera& camera);

    /// The wheel's multiplier of the fly speed (1 at first).
    double speedScale() const { return m_speedScale; }
    /// The speed keys would fly at now (without boost or slow), m/s, from the last update.
    double speedMps() const { return m_speedMps; }
    /// The camera's height above the ground at the last update, metres (may be negative
    /// when the floor is off).
    double heightAboveGroundM() const { return m_heightAboveGroundM; }
    const glm::dvec3& velocity() const { return m_velocity; }

private:
    void setSpeedScale(double scale);
    double flySpeed(double heightAboveGround) const;
    void flyStep(Camera& camera, const CameraInput& input, double stepS,
                 const GroundHeightFn& ground);
    void orbitKeys(Camera& camera, const CameraInput& input, double dtS);
    void placeOrbitCamera(Camera& camera, const GroundHeightFn& ground);
    void applyFloor(Camera& camera, const GroundHeightFn& ground);

    CameraControllerOptions m_options;
    CameraMode m_mode = CameraMode::Fly;
    glm::dvec3 m_velocity{0.0};
    glm::dvec3 m_pivot{0.0};
    double m_distance = 0.0;
    double m_speedScale = 1.0;
    double m_speedMps = 0.0;
    double m_heightAboveGroundM = 0.0;
};

/// The world direction (unit) of the view ray through window pixel (xPx, yPx), origin at the
/// top-left corner, +y down; (w/2, h/2) is camera.forward().
glm::dvec3 viewRay(const Camera& camera, double xPx, double yPx);

/// The world point at window pixel (xPx, yPx) whose reversed-Z depth (Camera::projection:
/// nearPlane / distance along the view axis) is `depth` > 0.
glm::dvec3 pointAtDepth(const Camera& camera, double xPx, double yPx, double depth);

/// Where a ray from above meets the plane z = planeZ, if that is at most maxDistanceM along
/// it; otherwise (sky, a grazing ray, a ray from below) the point maxDistanceM along it.
/// `direction` is a unit vector.
glm::dvec3 pointOnPlaneOrAhead(const glm::dvec3& origin, const glm::dvec3& direction, double planeZ,
                               double maxDistanceM);

}  // namespace terrain::runtime
