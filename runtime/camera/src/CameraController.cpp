// CameraController: fly and orbit controls integrated in fixed-size sub-steps.
#include "terrain/runtime/CameraController.h"

#include "terrain/base/Assert.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace terrain::runtime {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kMinSpeedScale = 1.0 / 256.0;
constexpr double kMaxSpeedScale = 256.0;
constexpr double kMaxOrbitDistanceM = 1.0e8;

// Yaw in [−π, π], so the number shown stays readable after many turns.
double wrapYaw(double yaw) { return std::remainder(yaw, kTwoPi); }

double modifierFactor(const CameraInput& input, const CameraControllerOptions& o) {
    return (input.boost ? o.boostFactor : 1.0) * (input.slow ? o.slowFactor : 1.0);
}

glm::dvec3 horizontalForward(const Camera& camera) {
    return {std::sin(camera.yaw), std::cos(camera.yaw), 0.0};
}

}  // namespace

CameraController::CameraController(const CameraControllerOptions& options) : m_options(options) {}

void CameraController::fly() {
    m_mode = CameraMode::Fly;
    m_velocity = glm::dvec3(0.0);
}

void CameraController::orbit(Camera& camera, const glm::dvec3& pivot) {
    m_mode = CameraMode::Orbit;
    m_velocity = glm::dvec3(0.0);
    m_pivot = pivot;
    const glm::dvec3 offset = camera.position - pivot;
    m_distance = glm::length(offset);
    if (m_distance > 0.0) camera.lookAt(pivot);
    placeOrbitCamera(camera, {});
}

void CameraController::setSpeedScale(double scale) {
    m_speedScale = std::clamp(scale, kMinSpeedScale, kMaxSpeedScale);
}

double CameraController::flySpeed(double heightAboveGround) const {
    const double speed = m_options.speedPerHeightPerS * std::max(heightAboveGround, 0.0);
    return std::clamp(speed, m_options.minSpeedMps, m_options.maxSpeedMps) * m_speedScale;
}

void CameraController::update(Camera& camera, const CameraInput& input, double dtS,
                              const GroundHeightFn& ground) {
    TERRAIN_ASSERT(ground, "CameraController::update needs a ground height function");
    const double look = m_options.lookRadiansPerPx;
    camera.yaw = wrapYaw(camera.yaw + input.lookDxPx * look);
    const double frameS = std::min(std::isfinite(dtS) ? dtS : 0.0, m_options.maxFrameS);

    if (m_mode == CameraMode::Fly) {
        camera.pitch =
            std::clamp(camera.pitch - input.lookDyPx * look, -Camera::kMaxPitch, Camera::kMaxPitch);
        if (input.wheelSteps != 0.0) {
            setSpeedScale(m_speedScale * std::pow(m_options.wheelSpeedStep, input.wheelSteps));
        }
        if (frameS > 0.0) {
            // Equal sub-steps no longer than maxStepS: the result hardly depends on how the
            // time was split into frames (and not at all when both splits give the same step).
            const double steps = std::ceil(frameS / m_options.maxStepS - 1e-9);
            const int count = std::max(1, static_cast<int>(steps));
            const double stepS = frameS / count;
            for (int i = 0; i < count; ++i) flyStep(camera, input, stepS, ground);
        } else {
            applyFloor(camera, ground);
        }
        m_heightAboveGroundM = camera.position.z - ground(camera.position.x, camera.position.y);
        m_speedMps = flySpeed(m_heightAboveGroundM);
        return;
    }

    camera.pitch = std::clamp(camera.pitch - input.lookDyPx * look, -Camera::kMaxPitch,
                              -m_options.orbitMinElevation);
    if (input.wheelSteps != 0.0) {
        m_distance *= std::pow(m_options.wheelZoomStep, input.wheelSteps);
    }
    if (frameS > 0.0) orbitKeys(camera, input, frameS);
    placeOrbitCamera(camera, ground);
    m_heightAboveGroundM = camera.position.z - ground(camera.position.x, camera.position.y);
    m_speedMps = m_distance * m_options.orbitPanPerS;
}

void CameraController::flyStep(Camera& camera, const CameraInput& input, double stepS,
                               const GroundHeightFn& ground) {
    const double height = camera.position.z - ground(camera.position.x, camera.position.y);
    const double speed = flySpeed(height) * modifierFactor(input, m_options);
    const auto axis = [](bool positive, bool negative) {
        return (positive ? 1.0 : 0.0) - (negative ? 1.0 : 0.0);
    };
    glm::dvec3 direction = camera.forward() * axis(input.forward, input.back) +
                           camera.right() * axis(input.right, input.left) +
                           glm::dvec3(0.0, 0.0, 1.0) * axis(input.up, input.down);
    const double length = glm::length(direction);
    if (length > 0.0) direction /= length;
    // Exact for a constant target over the sub-step: v approaches it as 1 − e^(−t/τ).
    const double blend =
        m_options.responseS > 0.0 ? 1.0 - std::exp(-stepS / m_options.responseS) : 1.0;
    m_velocity += (direction * speed - m_velocity) * blend;
    camera.position += m_velocity * stepS;
    applyFloor(camera, ground);
}

void CameraController::applyFloor(Camera& camera, const GroundHeightFn& ground) {
    if (!m_options.keepAboveGround || !ground) return;
    const double floor = ground(camera.position.x, camera.position.y) + m_options.clearanceM;
    if (camera.position.z < floor) {
        camera.position.z = floor;
        m_velocity.z = std::max(m_velocity.z, 0.0);
    }
}

void CameraController::orbitKeys(Camera& camera, const CameraInput& input, double dtS) {
    const double factor = modifierFactor(input, m_options);
    glm::dvec3 pan =
        horizontalForward(camera) * ((input.forward ? 1.0 : 0.0) - (input.back ? 1.0 : 0.0)) +
        camera.right() * ((input.right ? 1.0 : 0.0) - (input.left ? 1.0 : 0.0));
    const double length = glm::length(pan);
    if (length > 0.0) {
        m_pivot += pan / length * (m_distance * m_options.orbitPanPerS * factor * dtS);
    }
    const double zoom = (input.up ? 1.0 : 0.0) - (input.down ? 1.0 : 0.0);
    m_distance *= std::exp(zoom * m_options.orbitZoomPerS * factor * dtS);
}

void CameraController::placeOrbitCamera(Camera& camera, const GroundHeightFn& ground) {
    m_distance = std::clamp(m_distance, m_options.orbitMinDistanceM, kMaxOrbitDistanceM);
    camera.pitch = std::min(camera.pitch, -m_options.orbitMinElevation);
    camera.position = m_pivot - camera.forward() * m_distance;
    if (!m_options.keepAboveGround || !ground) return;
    const double floor = ground(camera.position.x, camera.position.y) + m_options.clearanceM;
    if (camera.position.z < floor) {
        // Raised over the ground, still looking at the pivot.
        camera.position.z = floor;
        camera.lookAt(m_pivot);
        m_distance = glm::length(camera.position - m_pivot);
    }
}

void CameraController::jumpTo(Camera& camera, double x, double y, double heightAboveGroundM,
                              const GroundHeightFn& ground) {
    TERRAIN_ASSERT(ground, "CameraController::jumpTo needs a ground height function");
    m_velocity = glm::dvec3(0.0);
    const double groundZ = ground(x, y);
    const double height = std::max(heightAboveGroundM, m_options.clearanceM);
    if (m_mode == CameraMode::Fly) {
        camera.position = {x, y, groundZ + height};
        camera.pitch = m_options.jumpPitch;
        return;
    }
    m_pivot = {x, y, groundZ};
    camera.pitch = std::min(m_options.jumpPitch, -m_options.orbitMinElevation);
    m_distance = height / std::sin(-camera.pitch);
    placeOrbitCamera(camera, ground);
}

void CameraController::cameraMovedExternally(Camera& camera) {
    m_velocity = glm::dvec3(0.0);
    if (m_mode == CameraMode::Orbit) {
        // Keep what the camera shows: the pivot moves to the point it now looks at.
        camera.pitch = std::min(camera.pitch, -m_options.orbitMinElevation);
        m_pivot = camera.position + camera.forward() * m_distance;
    }
}

glm::dvec3 viewRay(const Camera& camera, double xPx, double yPx) {
    const double ndcX = 2.0 * xPx / camera.viewportWidth - 1.0;
    const double ndcY = 1.0 - 2.0 * yPx / camera.viewportHeight;
    const double tanY = std::tan(0.5 * camera.fovY);
    const double tanX = tanY * camera.aspect();
    return glm::normalize(camera.forward() + camera.right() * (ndcX * tanX) +
                          camera.up() * (ndcY * tanY));
}

glm::dvec3 pointAtDepth(const Camera& camera, double xPx, double yPx, double depth) {
    const glm::dvec3 ray = viewRay(camera, xPx, yPx);
    const double alongAxis = camera.nearPlane / depth;
    return camera.position + ray * (alongAxis / glm::dot(ray, camera.forward()));
}

glm::dvec3 pointOnPlaneOrAhead(const glm::dvec3& origin, const glm::dvec3& direction, double planeZ,
                               double maxDistanceM) {
    if (direction.z < 0.0 && origin.z > planeZ) {
        const double t = (planeZ - origin.z) / direction.z;
        if (t <= maxDistanceM) return origin + direction * t;
    }
    return origin + direction * maxDistanceM;
}

}  // namespace terrain::runtime
