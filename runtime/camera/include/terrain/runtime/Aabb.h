// Aabb: an axis-aligned box in world metres (double), the bounding volume V of a patch in
// Yusov & Shevtsov 2011, §5: its footprint and its min/max heights.
#pragma once

#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>

namespace terrain::runtime {

struct Aabb {
    glm::dvec3 min{0.0};
    glm::dvec3 max{0.0};
};

/// ρ(c, V): the distance from `point` to the closest point of `box` (0 inside).
inline double distanceToBox(const glm::dvec3& point, const Aabb& box) {
    const double dx = std::max({box.min.x - point.x, 0.0, point.x - box.max.x});
    const double dy = std::max({box.min.y - point.y, 0.0, point.y - box.max.y});
    const double dz = std::max({box.min.z - point.z, 0.0, point.z - box.max.z});
    return std::sqrt(dx * dx + dy * dy + dz * dz);
}

}  // namespace terrain::runtime
