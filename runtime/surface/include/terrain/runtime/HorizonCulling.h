// HorizonCulling: Cesium's ellipsoidal occluder (DESIGN.md, "The globe"; Cesium's
// EllipsoidalOccluder and its "Horizon culling" blog post, 2013). In scaled space, where the
// ellipsoid is the unit sphere, a patch is summarised by one horizon culling point H on the
// ray through its centre: the lowest point from which every corner of its bounding box is on
// or below the horizon. If the camera cannot see H past the sphere, it cannot see the patch.
// The occluding ellipsoid is WGS84 shrunk by `shrink` metres, the depth of the deepest terrain
// (e.g. the Dead Sea, the ocean floor), so that the occluder lies inside the ground everywhere
// and never hides a visible pixel. A patch for which H does not exist (its corners span more
// than the hemisphere seen from the ray) is never culled by this test.
#pragma once

#include "terrain/globe/PatchBounds.h"

#include <glm/vec3.hpp>

#include <optional>
#include <span>

namespace terrain::runtime {

class EllipsoidalOccluder {
public:
    /// `shrink` ≥ 0: metres taken off each WGS84 radius.
    explicit EllipsoidalOccluder(double shrink = 0.0);

    /// The radii of the occluding ellipsoid, metres.
    glm::dvec3 radii() const { return m_radii; }

    /// Places the eye (ECEF metres); the visibility tests below are for this camera.
    void setCamera(const glm::dvec3& camera);

    /// Cesium's computeHorizonCullingPoint: the scaled-space horizon culling point of
    /// `positions` (ECEF) on the ray along `directionToPoint`, or nothing when no such point
    /// exists (a position faces away from the ray, or the point would be at infinity).
    std::optional<glm::dvec3> horizonCullingPoint(const glm::dvec3& directionToPoint,
                                                  std::span<const glm::dvec3> positions) const;

    /// Cesium's isScaledSpacePointVisible for the current camera. Below the occluder the
    /// culling plane is the one through the camera's scaled position.
    bool isScaledSpacePointVisible(const glm::dvec3& scaledPoint) const;

    /// True when the box is certainly hidden behind the occluder for the current camera: the
    /// horizon culling point of its 8 corners on the ray through its centre is not visible.
    bool isHidden(const globe::OrientedBox& box) const;

    glm::dvec3 toScaledSpace(const glm::dvec3& ecef) const { return ecef / m_radii; }

private:
    glm::dvec3 m_radii;
    glm::dvec3 m_scaledCamera{0.0};
    double m_limbDistanceSquared = 0.0;  ///< |scaled camera|² − 1 (negative below the occluder)
};

}  // namespace terrain::runtime
