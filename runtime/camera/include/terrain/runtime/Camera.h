// Camera: a perspective camera in the world frame (x east, y north, z up), position in
// double precision. Rendering uses camera-relative matrices (rotation and projection
// only), so float32 never holds a world coordinate (DESIGN.md, "Coordinates and
// precision").
#pragma once

#include "terrain/runtime/Aabb.h"

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <array>

namespace terrain::runtime {

/// Six inward-facing planes (n · p + d ≥ 0 inside) in world coordinates; the far plane is
/// at infinity and left out.
struct Frustum {
    std::array<glm::dvec4, 5> planes{};  // left, right, bottom, top, near

    /// False when the box lies entirely outside one plane (conservative: a box near a
    /// corner may pass although it is outside).
    bool intersects(const Aabb& box) const;
};

struct Camera {
    glm::dvec3 position{0.0};
    double yaw = 0.0;    ///< radians, 0 looks north, π/2 looks east (in `frame`)
    double pitch = 0.0;  ///< radians, positive looks up; clamped to ±kMaxPitch
    double fovY = 1.0;   ///< vertical field of view, radians
    int viewportWidth = 1;
    int viewportHeight = 1;
    double nearPlane = 0.5;  ///< metres; the projection is reversed-Z with an infinite far
    /// The world directions of the camera's local east, north and up (columns), which yaw
    /// and pitch are measured in: the identity for a planar pyramid (x east, y north, z up),
    /// the ellipsoid's east-north-up at the camera on a globe (placeOnGlobe, GlobeCamera.h).
    glm::dmat3 frame{1.0};

    static constexpr double kMaxPitch = 1.5690;  // 89.9°: keeps the up vector defined

    glm::dvec3 forward() const;
    glm::dvec3 right() const;
    glm::dvec3 up() const;

    double aspect() const;
    double fovX() const;  ///< horizontal field of view, radians
    /// γ = ½ max(R_h·ctg(φ_h/2), R_v·ctg(φ_v/2)) (Yusov & Shevtsov 2011, §5): pixels per
    /// metre of error at unit distance.
    double errorScale() const;

    /// World → camera-relative view: rotation only (translation by −position is done in
    /// double on the CPU before anything reaches the GPU).
    glm::dmat4 viewRotation() const;
    /// Reversed-Z infinite perspective for glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE):
    /// depth = nearPlane / distance along the view axis, 1 at the near plane, 0 at infinity.
    glm::dmat4 projection() const;
    /// projection() · viewRotation(): maps camera-relative positions to clip space.
    glm::dmat4 relativeViewProjection() const;

    Frustum frustum() const;

    /// Points the camera at `target` (world) from its position.
    void lookAt(const glm::dvec3& target);
};

}  // namespace terrain::runtime
