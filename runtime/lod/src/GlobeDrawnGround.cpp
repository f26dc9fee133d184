#include "terrain/runtime/GlobeDrawnGround.h"

#include "terrain/globe/Wgs84.h"

#include <algorithm>

namespace terrain::runtime {

double drawnGroundCeiling(std::span<const GlobePatchDraw> draws, const glm::dvec3& ecef) {
    const globe::FacePoint nadir = globe::facePointOf(globe::Wgs84::upAt(ecef));
    double ceiling = 0.0;
    for (const GlobePatchDraw& draw : draws) {
        if (draw.id.face != nadir.face) continue;
        const double n = static_cast<double>(globe::patchesPerFaceSide(draw.id.level));
        const double u = nadir.s * n - double(draw.id.x), v = nadir.t * n - double(draw.id.y);
        if (u >= 0.0 && u <= 1.0 && v >= 0.0 && v <= 1.0)
            ceiling = std::max(ceiling, double(draw.maxHeight));
    }
    return ceiling;
}

}  // namespace terrain::runtime
