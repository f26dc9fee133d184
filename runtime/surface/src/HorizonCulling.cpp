#include "terrain/runtime/HorizonCulling.h"

#include "terrain/globe/Wgs84.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace terrain::runtime {

EllipsoidalOccluder::EllipsoidalOccluder(double shrink)
    : m_radii(globe::Wgs84::kEquatorialRadius - shrink, globe::Wgs84::kEquatorialRadius - shrink,
              globe::Wgs84::kPolarRadius - shrink) {}

void EllipsoidalOccluder::setCamera(const glm::dvec3& camera) {
    m_scaledCamera = toScaledSpace(camera);
    m_limbDistanceSquared = glm::dot(m_scaledCamera, m_scaledCamera) - 1.0;
}

std::optional<glm::dvec3> EllipsoidalOccluder::horizonCullingPoint(
    const glm::dvec3& directionToPoint, std::span<const glm::dvec3> positions) const {
    const glm::dvec3 scaledDirection = toScaledSpace(directionToPoint);
    const double directionLength = glm::length(scaledDirection);
    if (directionLength == 0.0 || positions.empty()) return std::nullopt;
    const glm::dvec3 towardPoint = scaledDirection / directionLength;

    double magnitude = 0.0;
    for (const glm::dvec3& position : positions) {
        // Cesium's computeMagnitude: the distance along the ray of the apex of the cone that is
        // tangent to the unit sphere and passes through the position; positions below the
        // surface count as on it.
        const glm::dvec3 scaled = toScaledSpace(position);
        const double length = glm::length(scaled);
        if (length == 0.0) return std::nullopt;
        const glm::dvec3 direction = scaled / length;
        const double clampedSquared = std::max(1.0, length * length);
        const double clamped = std::max(1.0, length);
        const double cosAlpha = glm::dot(direction, towardPoint);
        const double sinAlpha = glm::length(glm::cross(direction, towardPoint));
        const double cosBeta = 1.0 / clamped;
        const double sinBeta = std::sqrt(clampedSquared - 1.0) * cosBeta;
        const double candidate = 1.0 / (cosAlpha * cosBeta - sinAlpha * sinBeta);
        // A negative candidate: this position is past the ray's horizon (the box spans too
        // much of the globe); no finite point summarises it.
        if (!(candidate >= 0.0)) return std::nullopt;
        magnitude = std::max(magnitude, candidate);
    }
    if (!(magnitude > 0.0) || !std::isfinite(magnitude)) return std::nullopt;
    return towardPoint * magnitude;
}

bool EllipsoidalOccluder::isScaledSpacePointVisible(const glm::dvec3& scaledPoint) const {
    const glm::dvec3 cameraToPoint = scaledPoint - m_scaledCamera;
    const double alongCamera = -glm::dot(cameraToPoint, m_scaledCamera);
    const bool occluded =
        m_limbDistanceSquared < 0.0
            ? alongCamera > 0.0
            : alongCamera > m_limbDistanceSquared &&
                  alongCamera * alongCamera / glm::dot(cameraToPoint, cameraToPoint) >
                      m_limbDistanceSquared;
    return !occluded;
}

bool EllipsoidalOccluder::isHidden(const globe::OrientedBox& box) const {
    const auto corners = box.corners();
    const std::optional<glm::dvec3> point = horizonCullingPoint(box.centre, corners);
    return point && !isScaledSpacePointVisible(*point);
}

}  // namespace terrain::runtime
