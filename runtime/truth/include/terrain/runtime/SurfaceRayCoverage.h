// SurfaceRayCoverage: whether a pixel's ray meets the full-resolution surface however its
// cells are split. The surface is a grid of samples; each cell may be drawn as two
// triangles along either diagonal, and the error measure accepts both (FullResolutionSurface).
// Where cells are so steep that the two diagonals are pixels apart (a needle forest), which
// pixel centres the surface covers depends on that choice, cell by cell; the LOD's
// tessellator makes its own. A pixel the LOD leaves clear is therefore a hole only if every
// choice covers it: if some cell on the ray is hit by both of its triangulations.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/runtime/FullResolutionSurface.h"

#include <glm/vec3.hpp>

namespace terrain::runtime {

/// True when the ray from world point `origin` along `direction` (z up, metres) meets the
/// full-resolution surface whichever diagonal splits each of its cells; false when some
/// choice lets it through (or it crosses no cell). With `lowerPerMetre` > 0 the surface is
/// first lowered, at each sample, by that much per metre of the sample's distance from
/// `origin`: the ray must meet it even so (see TruthSurface::everyTriangulationCovers).
/// Errors: a patch that cannot be read.
Result<bool> everyTriangulationCovers(FullResolutionSurface& surface, const glm::dvec3& origin,
                                      const glm::dvec3& direction, double lowerPerMetre = 0.0);

}  // namespace terrain::runtime
