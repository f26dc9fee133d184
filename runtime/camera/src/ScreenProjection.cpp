// ScreenProjection: the viewport transform and its inverse, in double.
#include "terrain/runtime/ScreenProjection.h"

#include <glm/vec4.hpp>

#include <limits>

namespace terrain::runtime {

glm::dvec3 unprojectPixel(const glm::dmat4& inverseViewProjection, int widthPx, int heightPx, int x,
                          int y, double depth) {
    // glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE): window depth is clip z / w itself.
    const glm::dvec4 ndc{(2.0 * (x + 0.5)) / widthPx - 1.0, (2.0 * (y + 0.5)) / heightPx - 1.0,
                         depth, 1.0};
    const glm::dvec4 p = inverseViewProjection * ndc;
    return glm::dvec3(p) / p.w;
}

glm::dvec2 projectToPixels(const glm::dmat4& viewProjection, int widthPx, int heightPx,
                           const glm::dvec3& relative) {
    const glm::dvec4 clip = viewProjection * glm::dvec4(relative, 1.0);
    if (!(clip.w > 0.0)) return glm::dvec2(std::numeric_limits<double>::quiet_NaN());
    return {(clip.x / clip.w + 1.0) * 0.5 * widthPx, (clip.y / clip.w + 1.0) * 0.5 * heightPx};
}

}  // namespace terrain::runtime
