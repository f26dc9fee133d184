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

/// Livny et al. 2007's d (Eq. 1) for the patch whose footprint is `box`'s: the distance
/// from `point` to the nearest of the footprint's four edges, each extruded vertically over
/// [lowM, highM] (the DEM's height range, so every patch sharing an edge measures it alike
/// and a part of an edge is never nearer than the edge). LivnyRenderer's control stage
/// (livny.tesc) computes the same per edge.
inline double livnyEdgeDistance(const glm::dvec3& point, const Aabb& box, double lowM,
                                double highM) {
    const double dz = std::max({lowM - point.z, 0.0, point.z - highM});
    // The nearest point of an edge along x (or y) is the point clamped to the edge's span.
    const double cx = std::clamp(point.x, box.min.x, box.max.x);
    const double cy = std::clamp(point.y, box.min.y, box.max.y);
    const double toWestOrEast =
        std::min(std::abs(point.x - box.min.x), std::abs(point.x - box.max.x));
    const double toSouthOrNorth =
        std::min(std::abs(point.y - box.min.y), std::abs(point.y - box.max.y));
    // West and east edges: x fixed, y clamped; south and north: y fixed, x clamped.
    const double alongY = std::abs(point.y - cy);
    const double alongX = std::abs(point.x - cx);
    const double d2 = std::min(toWestOrEast * toWestOrEast + alongY * alongY,
                               toSouthOrNorth * toSouthOrNorth + alongX * alongX);
    return std::sqrt(d2 + dz * dz);
}

}  // namespace terrain::runtime
