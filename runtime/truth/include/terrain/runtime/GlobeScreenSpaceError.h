// GlobeScreenSpaceError: the screen-space error a globe frame shows (docs/globe.md), measured
// per pixel as ScreenSpaceError.h measures a plane, with the ellipsoid's normal as the
// vertical: the LOD's depth is unprojected in double to W_lod, whose geodetic latitude,
// longitude and height follow exactly (GeographicLib); the full-resolution surface of the
// sources (io::GlobeSourceSurface, through a GlobeReferenceHeights) gives the height of the reference point W_ref on the same
// normal; both are projected, and their distance in pixels is the pixel's error (the nearer
// of the source cell's two diagonals, 0 between them).
//
// The reference may also be the pyramid's own finest level (io::GlobeGroundQuery): then the
// figure is the LOD's error alone, what it chose against what the pyramid holds, without the
// finest level's resampling of the sources (its Err(P), which no LOD can go below and which
// shows on screen once the camera is close enough to the ground).
#pragma once

#include "terrain/runtime/Camera.h"
#include "terrain/runtime/ScreenSpaceError.h"

#include <functional>
#include <span>
#include <utility>

namespace terrain::runtime {

/// A reference surface's heights at a latitude and longitude (degrees) on the two
/// triangulations of its cell there, metres along the ellipsoid normal.
using GlobeReferenceHeights = std::function<std::pair<double, double>(double, double)>;

/// `lodDepth`: the frame's depth (reversed Z, rows bottom-up, the camera's viewport);
/// `lodDepthNoSkirts`: the same frame without skirts (empty: every drawn pixel is surface).
ScreenSpaceErrorStats measureGlobeScreenSpaceError(const Camera& camera,
                                                   std::span<const float> lodDepth,
                                                   std::span<const float> lodDepthNoSkirts,
                                                   const GlobeReferenceHeights& reference,
                                                   double thresholdPx);

}  // namespace terrain::runtime
