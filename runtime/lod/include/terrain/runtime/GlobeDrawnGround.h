// GlobeDrawnGround: a height at or above the ground a frame drew under a point, from the
// frame's own draw list (no read, no GPU): the highest sample of the drawn patch that holds
// the point's nadir. The viewer keeps the camera above it and the stress flight flies over it.
#pragma once

#include "terrain/runtime/GlobeLod.h"

#include <glm/vec3.hpp>

#include <span>

namespace terrain::runtime {

/// The largest maxHeight of the drawn patches whose face square holds the nadir of `ecef`
/// (a patch edge belongs to both sides); 0 (the ellipsoid) where none does, e.g. when the
/// nadir was culled.
double drawnGroundCeiling(std::span<const GlobePatchDraw> draws, const glm::dvec3& ecef);

}  // namespace terrain::runtime
