// cameraRelativeFrustumPlanes: the camera's five frustum planes (Camera::frustum) moved to
// the camera-relative frame the shaders work in, unit normals pointing inside, packed as
// vec4s for a `uniform vec4 u_frustumPlanes[5]` (the GPU-side LOD methods cull with them).
#pragma once

#include "terrain/runtime/Camera.h"

#include <array>

namespace terrain::runtime {

std::array<float, 20> cameraRelativeFrustumPlanes(const Camera& camera);

}  // namespace terrain::runtime
