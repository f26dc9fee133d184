#include "terrain/runtime/GlobeInstance.h"

#include "terrain/globe/SurfaceOffset.h"
#include "terrain/globe/Wgs84.h"
#include "terrain/pyramid/GlobeLayout.h"

#include <glm/geometric.hpp>

#include <algorithm>

namespace terrain::runtime {
namespace {

// Metres per tile sample along s and t at patch coordinates (u, v), for the shading normal:
// a patch sample's spacing over `texelStep` (tile samples per patch sample).
std::array<float, 4> sampleSpacing(const globe::GlobePatchId& id, int quads, double u, double v,
                                   double texelStep) {
    constexpr double kStep = 1e-3;
    const auto at = [&](double pu, double pv) {
        const globe::FacePoint p =
            globe::patchPoint(id, std::clamp(pu, 0.0, 1.0), std::clamp(pv, 0.0, 1.0));
        return globe::Wgs84::pointAlongNormal(globe::directionOf(p.face, p.s, p.t), 0.0);
    };
    const double du =
        glm::distance(at(u - kStep, v), at(u + kStep, v)) / (2.0 * kStep) / quads / texelStep;
    const double dv =
        glm::distance(at(u, v - kStep), at(u, v + kStep)) / (2.0 * kStep) / quads / texelStep;
    return {static_cast<float>(du), static_cast<float>(dv), 0.0f, 0.0f};
}

}  // namespace

GlobeInstance makeGlobeInstance(const PatchDraw& p, const glm::dvec3& camera,
                                const glm::dvec3& cameraUp, int patchQuads) {
    const globe::GlobePatchId id = io::globePatchOf(p.id);
    const glm::dvec2 uv0 = globe::nearestPatchCoordinates(id, cameraUp);
    const globe::PatchSurfaceFrame f = globe::makePatchSurfaceFrame(id, uv0.x, uv0.y, camera);
    return {{f.alphaPerU, f.u0, f.v0, f.alpha0},
            {f.beta0, f.cubeS0, f.cubeT0, f.inverseLength0},
            {f.direction0.x, f.direction0.y, f.direction0.z, f.sqrtG0},
            {f.originFromCamera.x, f.originFromCamera.y, f.originFromCamera.z, f.primeVertical0},
            {p.errorM, p.skirtDepthM, p.minHeight, p.maxHeight},
            p.bareBlockErrorsM,
            sampleSpacing(id, patchQuads, uv0.x, uv0.y, p.texelStep),
            {p.texelOffset[0], p.texelOffset[1], p.texelStep, p.isVirtual ? 1.0f : 0.0f},
            {p.layer, id.level, id.face, 0}};
}

}  // namespace terrain::runtime
