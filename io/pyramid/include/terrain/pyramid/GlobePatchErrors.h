// GlobePatchErrors: the tessellation-block errors λ(d) of a globe patch (Yusov & Shevtsov 2011,
// §5, on the ellipsoid). In the face grid a block simplified by 2^d deviates from the full
// block as in a planar patch (patchBlockErrors); on the globe its flat triangles also cut
// under the curved surface, by up to flatTriangleErrorBound of their longer sides, which a
// planar λ(d) never had to hold. The builder stores this and terrain-inspect --verify
// recomputes it, so both call this one function.
#pragma once

#include "terrain/pyramid/PatchErrors.h"

#include <span>

namespace terrain::io {

/// λ(1..4) of every block of the patch `interior` (its N × N samples) at face level
/// `faceLevel`, whose lowest sample is `minHeight` metres: planar λ(d) plus the bulge of
/// the ellipsoid over a triangle with sides 2^d face-grid spacings long, rounded up.
void globePatchBlockErrors(const GridView& interior, int blockQuads, int faceLevel, float minHeight,
                           std::span<BlockErrors> out);

}  // namespace terrain::io
