// GlobeTruth: heights along the ellipsoid normal through the drawn point.
#include "terrain/runtime/GlobeTruth.h"

#include "terrain/globe/Wgs84.h"

#include <algorithm>

namespace terrain::runtime {

Result<TruthVertical> GlobeTruth::verticalAt(const glm::dvec3& world, const glm::dvec3&,
                                             const FrameProjection&) {
    const globe::Geodetic drawn = globe::Wgs84::toGeodetic(world);
    auto heights = m_heights(drawn.latitudeDeg, drawn.longitudeDeg);
    if (!heights) return heights.error();
    // The first (a–d) diagonal's height is what the fixed-diagonal figures compare with.
    const auto [alongAD, alongBC] = heights.value();
    return TruthVertical{.inside = true,
                         .drawnM = drawn.height,
                         .lowM = std::min(alongAD, alongBC),
                         .highM = std::max(alongAD, alongBC),
                         .referenceM = alongAD,
                         .up = globe::Wgs84::normalAt(drawn.latitudeDeg, drawn.longitudeDeg)};
}

glm::dvec3 GlobeTruth::relativePointAt(const TruthVertical& vertical, const glm::dvec3&,
                                       const FrameProjection& frame, double heightM) const {
    return globe::Wgs84::pointAlongNormal(vertical.up, heightM) - frame.cameraPosition;
}

}  // namespace terrain::runtime
