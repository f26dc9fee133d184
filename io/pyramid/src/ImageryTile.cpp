#include "terrain/pyramid/ImageryTile.h"

#include "terrain/pyramid/PyramidManifest.h"

#include <cmath>

namespace terrain::io {

PlanarSamplePoint planarImageryPoint(const PyramidLayout& layout, const PatchId& id, double u,
                                     double v) {
    // A patch of level l spans (N − 1) · 2^(finest − l) finest samples, for l past the finest
    // too (a fraction of a sample per texel there).
    const double span = std::ldexp(static_cast<double>(layout.patchQuads()),
                                   layout.finestLevel() - id.level);
    return {(static_cast<double>(id.x) + u) * span, (static_cast<double>(id.y) + v) * span};
}

globe::FacePoint globeImageryPoint(const PatchId& id, double u, double v) {
    const int faceLevel = id.level - ManifestGlobe::kLevelOffset;
    const std::int64_t perFace = std::int64_t{1} << faceLevel;
    const std::int64_t face = id.x / perFace;
    const double x = static_cast<double>(id.x - face * perFace);
    const double scale = std::ldexp(1.0, -faceLevel);
    return {static_cast<int>(face), (x + u) * scale, (static_cast<double>(id.y) + v) * scale};
}

}  // namespace terrain::io
