#include "terrain/globe/PatchBounds.h"

#include "terrain/globe/Wgs84.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace terrain::globe {

namespace {

constexpr int kGridQuads = 32;

}  // namespace

std::array<glm::dvec3, 8> OrientedBox::corners() const {
    std::array<glm::dvec3, 8> result{};
    for (int i = 0; i < 8; ++i) {
        const double sx = (i & 1) ? 1.0 : -1.0;
        const double sy = (i & 2) ? 1.0 : -1.0;
        const double sz = (i & 4) ? 1.0 : -1.0;
        result[i] = centre + sx * halfExtents.x * axes[0] + sy * halfExtents.y * axes[1] +
                    sz * halfExtents.z * axes[2];
    }
    return result;
}

OrientedBox patchBounds(const GlobePatchId& id, double minHeight, double maxHeight) {
    const FacePoint middle = patchPoint(id, 0.5, 0.5);
    const glm::dvec3 up = directionOf(middle.face, middle.s, middle.t);
    const glm::dvec3 right = glm::dvec3(faceFrame(id.face).right);
    const glm::dvec3 east = glm::normalize(right - glm::dot(right, up) * up);
    const glm::dvec3 south = glm::cross(up, east);
    const std::array<glm::dvec3, 3> axes{east, south, up};

    glm::dvec3 low(std::numeric_limits<double>::max());
    glm::dvec3 high(std::numeric_limits<double>::lowest());
    // The box of the grid points is not yet conservative: the surface bulges between them. A
    // point between the grid's directions is within flatTriangleErrorBound of a grid triangle,
    // whose corners are in the box, so the box is padded by that bound; a point between the
    // two heights lies on the segment between its two height points (a point moves linearly
    // with height along a fixed normal), so the two heights are enough.
    for (int j = 0; j <= kGridQuads; ++j) {
        for (int i = 0; i <= kGridQuads; ++i) {
            const FacePoint p = patchSamplePoint(id, kGridQuads, i, j);
            const glm::dvec3 direction = directionOf(p.face, p.s, p.t);
            for (const double height : {minHeight, maxHeight}) {
                const glm::dvec3 point = Wgs84::pointAlongNormal(direction, height);
                for (int axis = 0; axis < 3; ++axis) {
                    const double coordinate = glm::dot(point, axes[axis]);
                    low[axis] = std::min(low[axis], coordinate);
                    high[axis] = std::max(high[axis], coordinate);
                }
            }
        }
    }
    const double gridSpacing = maxSampleAngle(id.level, kGridQuads) *
                               (Wgs84::kMaxCurvatureRadius + std::max(maxHeight, 0.0));
    const double bulge = flatTriangleErrorBound(gridSpacing, minHeight);
    // Rounding of the dot products above: a few ulps of the planet's radius.
    const double pad = bulge + 1e-6 * (1.0 + std::abs(maxHeight)) + 1e-8 * Wgs84::kEquatorialRadius;

    OrientedBox box;
    box.axes = axes;
    glm::dvec3 centreInAxes{0.0};
    for (int axis = 0; axis < 3; ++axis) {
        low[axis] -= pad;
        high[axis] += pad;
        centreInAxes[axis] = 0.5 * (low[axis] + high[axis]);
        box.halfExtents[axis] = 0.5 * (high[axis] - low[axis]);
    }
    box.centre = centreInAxes.x * axes[0] + centreInAxes.y * axes[1] + centreInAxes.z * axes[2];
    return box;
}

double distanceToBox(const glm::dvec3& point, const OrientedBox& box) {
    const glm::dvec3 offset = point - box.centre;
    double squared = 0.0;
    for (int axis = 0; axis < 3; ++axis) {
        const double along = glm::dot(offset, box.axes[axis]);
        const double outside = std::max(std::abs(along) - box.halfExtents[axis], 0.0);
        squared += outside * outside;
    }
    return std::sqrt(squared);
}

}  // namespace terrain::globe
