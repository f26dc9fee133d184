#include "terrain/runtime/GlobeFrustum.h"

#include <glm/geometric.hpp>

#include <cmath>

namespace terrain::runtime {

bool frustumMeetsBox(const Frustum& frustum, const globe::OrientedBox& box) {
    for (const glm::dvec4& plane : frustum.planes) {
        const glm::dvec3 n(plane);
        // The box's reach towards the plane's normal: its half extents projected on it.
        double reach = 0.0;
        for (int axis = 0; axis < 3; ++axis)
            reach += std::abs(glm::dot(n, box.axes[axis])) * box.halfExtents[axis];
        if (glm::dot(n, box.centre) + plane.w + reach < 0.0) return false;
    }
    return true;
}

}  // namespace terrain::runtime
