// cameraRelativeFrustumPlanes: n · (p + eye) + d = n · p + (d + n · eye), normalised.
#include "terrain/runtime/FrustumUniform.h"

#include <glm/geometric.hpp>

namespace terrain::runtime {

std::array<float, 20> cameraRelativeFrustumPlanes(const Camera& camera) {
    const Frustum frustum = camera.frustum();
    std::array<float, 20> planes{};
    for (std::size_t i = 0; i < frustum.planes.size(); ++i) {
        const glm::dvec4 p = frustum.planes[i];
        const double length = glm::length(glm::dvec3(p));
        const double d = p.w + glm::dot(glm::dvec3(p), camera.position);
        planes[4 * i] = static_cast<float>(p.x / length);
        planes[4 * i + 1] = static_cast<float>(p.y / length);
        planes[4 * i + 2] = static_cast<float>(p.z / length);
        planes[4 * i + 3] = static_cast<float>(d / length);
    }
    return planes;
}

}  // namespace terrain::runtime
