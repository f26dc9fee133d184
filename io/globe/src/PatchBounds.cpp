#include "terrain/globe/PatchBounds.h"

#include "terrain/globe/Wgs84.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

namespace terrain::globe {

namespace {

constexpr int kGridQuads = 32;

// The smallest of a few boxes around `points`, turned about `up` from `east`, padded by
// `pad`.
OrientedBox boxAround(const std::vector<glm::dvec3>& points, const glm::dvec3& up,
                      const glm::dvec3& east, double pad);

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

    // The box of the grid points is not yet conservative: the surface bulges between them. A
    // point between the grid's directions is within flatTriangleErrorBound of a grid triangle,
    // whose corners are in the box, so the box is padded by that bound; a point between the
    // two heights lies on the segment between its two height points (a point moves linearly
    // with height along a fixed normal), so the two heights are enough.
    std::vector<glm::dvec3> points;
    points.reserve(2 * (kGridQuads + 1) * (kGridQuads + 1));
    for (int j = 0; j <= kGridQuads; ++j) {
        for (int i = 0; i <= kGridQuads; ++i) {
            const FacePoint p = patchSamplePoint(id, kGridQuads, i, j);
            const glm::dvec3 direction = directionOf(p.face, p.s, p.t);
            for (const double height : {minHeight, maxHeight})
                points.push_back(Wgs84::pointAlongNormal(direction, height));
        }
    }
    const double gridSpacing = maxSampleAngle(id.level, kGridQuads) *
                               (Wgs84::kMaxCurvatureRadius + std::max(maxHeight, 0.0));
    const double bulge = flatTriangleErrorBound(gridSpacing, minHeight);
    // Rounding of the dot products: a few ulps of the planet's radius.
    return boxAround(points, up, east,
                     bulge + 1e-6 * (1.0 + std::abs(maxHeight)) + 1e-8 * Wgs84::kEquatorialRadius);
}

OrientedBox nativeTileBounds(const NativeGridGeometry& grid, std::int64_t x, std::int64_t y,
                             double minHeight, double maxHeight, const NativeWindow& window) {
    // A window's box is made as it splits, four at a time: a coarser grid of places, padded
    // for its wider bulge, keeps that cheap.
    const int places = window.depth == 0 ? kGridQuads : 8;
    const double u0 = window.u0(), v0 = window.v0(), size = window.size();
    const glm::dvec2 middle = grid.lonLatDeg(x, y, u0 + 0.5 * size, v0 + 0.5 * size);
    const glm::dvec3 up = Wgs84::normalAt(std::clamp(middle.y, -90.0, 90.0), middle.x);
    // East, but any direction square to up at a pole.
    const glm::dvec3 east = std::hypot(up.x, up.y) > 1e-9
                                ? glm::normalize(glm::dvec3(-up.y, up.x, 0.0))
                                : glm::dvec3(0.0, 1.0, 0.0);
    std::vector<glm::dvec3> points;
    points.reserve(2 * static_cast<std::size_t>((places + 1) * (places + 1)));
    for (int j = 0; j <= places; ++j) {
        for (int i = 0; i <= places; ++i) {
            const glm::dvec2 at = grid.lonLatDeg(x, y, u0 + size * double(i) / places,
                                                 v0 + size * double(j) / places);
            const glm::dvec3 direction = Wgs84::normalAt(std::clamp(at.y, -90.0, 90.0), at.x);
            for (const double height : {minHeight, maxHeight})
                points.push_back(Wgs84::pointAlongNormal(direction, height));
        }
    }
    const double radian = std::numbers::pi / 180.0;
    const double step = double(grid.quads) * size / places;
    // The largest angle between neighbouring grid places, radians.
    const double widest = std::max(grid.pixelLonDeg, grid.pixelLatDeg) * step * radian;
    const double gridSpacing = widest * (Wgs84::kMaxCurvatureRadius + std::max(maxHeight, 0.0));
    const double bulge = flatTriangleErrorBound(gridSpacing, minHeight);
    return boxAround(points, up, east,
                     bulge + 1e-6 * (1.0 + std::abs(maxHeight)) + 1e-8 * Wgs84::kEquatorialRadius);
}

namespace {

OrientedBox boxAround(const std::vector<glm::dvec3>& points, const glm::dvec3& up,
                      const glm::dvec3& east, double pad) {
    const glm::dvec3 south = glm::cross(up, east);
    // Near a cube corner a patch is a rhombus (60° and 120°), loose in a box square to its
    // edges: the tangent axes are turned to the smallest footprint of a few candidates.
    OrientedBox best;
    double bestArea = std::numeric_limits<double>::max();
    for (int turn = 0; turn < 6; ++turn) {
        const double angle = turn * (std::numbers::pi / 12.0);
        const glm::dvec3 x = std::cos(angle) * east + std::sin(angle) * south;
        const std::array<glm::dvec3, 3> axes{x, glm::cross(up, x), up};
        glm::dvec3 low(std::numeric_limits<double>::max());
        glm::dvec3 high(std::numeric_limits<double>::lowest());
        for (const glm::dvec3& point : points) {
            for (int axis = 0; axis < 3; ++axis) {
                const double coordinate = glm::dot(point, axes[axis]);
                low[axis] = std::min(low[axis], coordinate);
                high[axis] = std::max(high[axis], coordinate);
            }
        }
        const double area = (high.x - low.x) * (high.y - low.y);
        if (area >= bestArea) continue;
        bestArea = area;
        best.axes = axes;
        best.centre = glm::dvec3(0.0);
        for (int axis = 0; axis < 3; ++axis) {
            best.halfExtents[axis] = 0.5 * (high[axis] - low[axis]);
            best.centre += 0.5 * (low[axis] + high[axis]) * axes[axis];
        }
    }
    best.halfExtents += glm::dvec3(pad);
    return best;
}

}  // namespace

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
