// Camera: yaw/pitch orientation, reversed-Z projection, frustum planes built in camera
// space and rotated into the world.
#include "terrain/runtime/Camera.h"

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>

namespace terrain::runtime {

bool Frustum::intersects(const Aabb& box) const {
    for (const glm::dvec4& plane : planes) {
        // The box corner furthest along the plane normal (the "p-vertex").
        const glm::dvec3 p{plane.x >= 0.0 ? box.max.x : box.min.x,
                           plane.y >= 0.0 ? box.max.y : box.min.y,
                           plane.z >= 0.0 ? box.max.z : box.min.z};
        if (plane.x * p.x + plane.y * p.y + plane.z * p.z + plane.w < 0.0) {
            return false;
        }
    }
    return true;
}

glm::dvec3 Camera::forward() const {
    const double p = std::clamp(pitch, -kMaxPitch, kMaxPitch);
    return frame *
           glm::dvec3(std::sin(yaw) * std::cos(p), std::cos(yaw) * std::cos(p), std::sin(p));
}

glm::dvec3 Camera::right() const { return frame * glm::dvec3(std::cos(yaw), -std::sin(yaw), 0.0); }

glm::dvec3 Camera::up() const { return glm::cross(right(), forward()); }

double Camera::aspect() const {
    return static_cast<double>(viewportWidth) / static_cast<double>(viewportHeight);
}

double Camera::fovX() const { return 2.0 * std::atan(std::tan(0.5 * fovY) * aspect()); }

double Camera::errorScale() const {
    const double horizontal = static_cast<double>(viewportWidth) / std::tan(0.5 * fovX());
    const double vertical = static_cast<double>(viewportHeight) / std::tan(0.5 * fovY);
    return 0.5 * std::max(horizontal, vertical);
}

glm::dmat4 Camera::viewRotation() const { return glm::lookAt(glm::dvec3(0.0), forward(), up()); }

glm::dmat4 Camera::projection() const {
    const double f = 1.0 / std::tan(0.5 * fovY);
    glm::dmat4 m(0.0);
    m[0][0] = f / aspect();
    m[1][1] = f;
    m[2][3] = -1.0;       // w_clip = −z_view (distance in front of the camera)
    m[3][2] = nearPlane;  // z_clip = near, so depth = near / distance
    return m;
}

glm::dmat4 Camera::relativeViewProjection() const { return projection() * viewRotation(); }

Frustum Camera::frustum() const {
    const double tanX = std::tan(0.5 * fovX());
    const double tanY = std::tan(0.5 * fovY);
    const glm::dvec3 r = right(), u = up(), f = forward();
    // Inward normals in camera space (x right, y up, z forward), rotated to the world.
    const auto plane = [&](double nx, double ny, double nz, double offset) {
        const glm::dvec3 n = glm::normalize(nx * r + ny * u + nz * f);
        return glm::dvec4(n, -glm::dot(n, position) - offset);
    };
    Frustum frustum;
    frustum.planes = {plane(1.0, 0.0, tanX, 0.0), plane(-1.0, 0.0, tanX, 0.0),
                      plane(0.0, 1.0, tanY, 0.0), plane(0.0, -1.0, tanY, 0.0),
                      plane(0.0, 0.0, 1.0, nearPlane)};
    return frustum;
}

void Camera::lookAt(const glm::dvec3& target) {
    const glm::dvec3 d = glm::transpose(frame) * (target - position);  // in the local frame
    const double horizontal = std::hypot(d.x, d.y);
    yaw = std::atan2(d.x, d.y);
    pitch = std::clamp(std::atan2(d.z, horizontal), -kMaxPitch, kMaxPitch);
}

}  // namespace terrain::runtime
