// PlaneTruth: heights straight above or below on the full-resolution DEM.
#include "terrain/runtime/PlaneTruth.h"

#include "terrain/runtime/SurfaceRayCoverage.h"

#include <glm/geometric.hpp>

#include <algorithm>

namespace terrain::runtime {
namespace {

TruthVertical verticalOf(const SurfaceHeight& s, double drawnM) {
    return {.inside = s.inside,
            .drawnM = drawnM,
            .lowM = s.lowM,
            .highM = s.highM,
            .referenceM = s.referenceM};
}

}  // namespace

Result<TruthVertical> PlaneTruth::verticalAt(const glm::dvec3& world, const glm::dvec3& relative,
                                             const FrameProjection& frame) {
    auto below = m_surface.heightAt(world.x, world.y);
    if (!below) return below.error();
    if (!below.value().inside) {
        const glm::dvec2 edge = m_surface.clampToDem(world.x, world.y);
        const glm::dvec3 edgeRelative{edge.x - frame.cameraPosition.x,
                                      edge.y - frame.cameraPosition.y, relative.z};
        if (glm::length(frame.toPixels(relative) - frame.toPixels(edgeRelative)) < 1.0) {
            below = m_surface.heightAt(edge.x, edge.y);
            if (!below) return below.error();
        }
    }
    return verticalOf(below.value(), world.z);
}

glm::dvec3 PlaneTruth::relativePointAt(const TruthVertical& vertical, const glm::dvec3& relative,
                                       const FrameProjection&, double heightM) const {
    return relative + glm::dvec3(0, 0, heightM - vertical.drawnM);
}

// The drawn point is where the rasteriser put it, which may be the tolerance off the exact
// triangle sideways (vertex snapping, float positions); on a slope S that is S times as far
// vertically (a cliff of slope 1,000 seen from 1 km: 1/256 px of snapping is 7 m, 4 px).
Result<TruthVertical> PlaneTruth::widened(const TruthVertical& vertical, const glm::dvec3& world,
                                          double radiusM) {
    auto range = m_surface.heightRange(world.x, world.y, radiusM);
    if (!range) return range.error();
    const HeightRange& r = range.value();
    TruthVertical wide = vertical;
    if (r.inside) {
        wide.lowM = std::min(vertical.lowM, r.lowM);
        wide.highM = std::max(vertical.highM, r.highM);
    }
    return wide;
}

Result<bool> PlaneTruth::everyTriangulationCovers(const glm::dvec3& cameraPosition,
                                                  const glm::dvec3& along, double lowerPerMetre) {
    return runtime::everyTriangulationCovers(m_surface, cameraPosition, along, lowerPerMetre);
}

}  // namespace terrain::runtime
