// ScreenProjection: between pixels and camera-relative points under a camera's matrices
// (reversed Z, glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE)), in double: what the measured
// error unprojects and projects, and what the LOD's screen bounds are tested against.
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace terrain::runtime {

/// Camera-relative position of pixel (x, y)'s centre (rows bottom-up) at reversed-Z depth
/// `depth` > 0, from `inverseViewProjection` = inverse(relativeViewProjection).
glm::dvec3 unprojectPixel(const glm::dmat4& inverseViewProjection, int widthPx, int heightPx, int x,
                          int y, double depth);

/// Pixel coordinates (x right, y up, from the lower-left corner) of a camera-relative point;
/// NaN when it lies behind the camera (clip w ≤ 0).
glm::dvec2 projectToPixels(const glm::dmat4& viewProjection, int widthPx, int heightPx,
                           const glm::dvec3& relative);

}  // namespace terrain::runtime
