#include "terrain/runtime/GlobeController.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace terrain::runtime {
namespace {

constexpr double kRadiansPerDegree = std::numbers::pi / 180.0;
constexpr double kPoleLimitDeg = 89.9999;

}  // namespace

void GlobeController::update(GlobePose& pose, const GlobeControlInput& input, double dtS,
                             double floorM) const {
    const GlobeControllerOptions& o = m_options;
    const double heightAbove = std::max(pose.where.height - floorM, o.minClearanceM);
    const CameraInput& held = input.held;
    if (input.lookAround) {
        pose.headingDeg = std::remainder(
            pose.headingDeg + held.lookDxPx * o.lookRadiansPerPx / kRadiansPerDegree, 360.0);
        pose.pitchDeg = std::clamp(
            pose.pitchDeg - held.lookDyPx * o.lookRadiansPerPx / kRadiansPerDegree, -90.0, 89.0);
    } else if (held.lookDxPx != 0.0 || held.lookDyPx != 0.0) {
        // The ground under the cursor follows it: a pixel covers height / focal metres there.
        const double metresPerPx = heightAbove / std::max(input.focalPx, 1.0);
        moveOverGround(pose, held.lookDyPx * metresPerPx, -held.lookDxPx * metresPerPx);
    }
    double speed = std::clamp(heightAbove * o.speedPerHeightPerS, o.minSpeedMps, o.maxSpeedMps);
    if (held.boost) speed *= o.boostFactor;
    if (held.slow) speed *= o.slowFactor;
    const double forward = (held.forward ? 1.0 : 0.0) - (held.back ? 1.0 : 0.0);
    const double right = (held.right ? 1.0 : 0.0) - (held.left ? 1.0 : 0.0);
    if (forward != 0.0 || right != 0.0)
        moveOverGround(pose, forward * speed * dtS, right * speed * dtS);
    const double climb = (held.up ? 1.0 : 0.0) - (held.down ? 1.0 : 0.0);
    double above = heightAbove * std::exp(climb * o.climbPerS * dtS);
    if (held.wheelSteps != 0.0) {
        const double factor = std::pow(o.wheelZoomStep, held.wheelSteps);
        above *= factor;
        if (input.zoomToward && factor < 1.0) {
            // Closer to the point under the cursor by the fraction the height fell.
            const double pull = 1.0 - factor;
            double dLon =
                std::remainder(input.zoomToward->longitudeDeg - pose.where.longitudeDeg, 360.0);
            pose.where.latitudeDeg +=
                pull * (input.zoomToward->latitudeDeg - pose.where.latitudeDeg);
            pose.where.longitudeDeg = std::remainder(pose.where.longitudeDeg + pull * dLon, 360.0);
        }
    }
    pose.where.height = std::clamp(floorM + std::max(above, o.minClearanceM),
                                   floorM + o.minClearanceM, o.maxHeightM);
}

GlobePose GlobeController::overExtent(double west, double south, double east, double north,
                                      double fovY) {
    const double span = east >= west ? east - west : east + 360.0 - west;
    double longitude = west + 0.5 * span;
    if (longitude > 180.0) longitude -= 360.0;
    const double latitude = 0.5 * (south + north);
    const double widthM = std::max(span * std::cos(latitude * kRadiansPerDegree), north - south) *
                          kRadiansPerDegree * globe::Wgs84::kEquatorialRadius;
    GlobePose pose;
    pose.where = {latitude, longitude,
                  std::clamp(0.6 * widthM / std::tan(0.5 * fovY), 2000.0, 20e6)};
    pose.headingDeg = 0.0;
    pose.pitchDeg = -90.0;
    return pose;
}

// Locally flat steps: a frame's motion is small against the planet.
void GlobeController::moveOverGround(GlobePose& pose, double forwardM, double rightM) {
    const double heading = pose.headingDeg * kRadiansPerDegree;
    const double northM = forwardM * std::cos(heading) - rightM * std::sin(heading);
    const double eastM = forwardM * std::sin(heading) + rightM * std::cos(heading);
    const double radius = globe::Wgs84::kEquatorialRadius;
    globe::Geodetic& where = pose.where;
    where.latitudeDeg = std::clamp(where.latitudeDeg + northM / radius / kRadiansPerDegree,
                                   -kPoleLimitDeg, kPoleLimitDeg);
    where.longitudeDeg +=
        eastM / (radius * std::cos(where.latitudeDeg * kRadiansPerDegree)) / kRadiansPerDegree;
    where.longitudeDeg = std::remainder(where.longitudeDeg, 360.0);
}

GlobePose GlobeController::wholeEarth(double latitudeDeg, double longitudeDeg) {
    return {{latitudeDeg, longitudeDeg, 20e6}, 0.0, -90.0};
}

}  // namespace terrain::runtime
