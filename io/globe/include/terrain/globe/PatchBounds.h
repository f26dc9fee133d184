// PatchBounds: the true bounding volume of a globe patch in ECEF metres, heights included
// (DESIGN.md, "The globe", LOD): an oriented box around the patch's surface between its
// minimum and maximum heights, the region-to-box idea of Cesium's
// OrientedBoundingBox.fromRectangle. The LOD's screen-space error divides by the distance to
// it, so the same view needs about the same patches at a pole, on the equator and at a cube
// corner; horizon culling takes its corners.
#pragma once

#include "terrain/globe/GlobePatch.h"
#include "terrain/globe/NativeOffset.h"

#include <glm/vec3.hpp>

#include <array>

namespace terrain::globe {

struct OrientedBox {
    glm::dvec3 centre{0.0};
    std::array<glm::dvec3, 3> axes{};  ///< orthonormal: east-ish, south-ish, the centre normal
    glm::dvec3 halfExtents{0.0};       ///< along each axis, metres

    std::array<glm::dvec3, 8> corners() const;
};

/// A box that holds every point of the patch at heights in [minHeight, maxHeight]. Built from
/// a 33 × 33 grid of the patch's directions at both heights, padded by how far the surface
/// can bulge between grid points (flatTriangleErrorBound), so it is conservative, not sampled.
OrientedBox patchBounds(const GlobePatchId& id, double minHeight, double maxHeight);

/// The same for tile (x, y) of a native grid (NativeOffset.h), or a window of it: its 33 × 33
/// grid of places by longitude and latitude (9 × 9 for a window below the tile) at both
/// heights, padded for the bulge between them.
OrientedBox nativeTileBounds(const NativeGridGeometry& grid, std::int64_t x, std::int64_t y,
                             double minHeight, double maxHeight, const NativeWindow& window = {});

/// The distance from `point` to the closest point of `box` (0 inside).
double distanceToBox(const glm::dvec3& point, const OrientedBox& box);

}  // namespace terrain::globe
