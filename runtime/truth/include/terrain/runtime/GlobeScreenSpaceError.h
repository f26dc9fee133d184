// GlobeScreenSpaceError: the screen-space error a globe frame shows (docs/globe.md), measured
// per pixel as ScreenSpaceError.h measures a plane, with the ellipsoid's normal as the
// vertical: the LOD's depth is unprojected in double to W_lod, whose geodetic latitude,
// longitude and height follow exactly (GeographicLib); the full-resolution surface of the
// sources (io::GlobeSourceSurface) gives the height of the reference point W_ref on the same
// normal; both are projected, and their distance in pixels is the pixel's error (the nearer
// of the source cell's two diagonals, 0 between them).
#pragma once

#include "terrain/io/GlobeSourceSurface.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/ScreenSpaceError.h"

#include <span>

namespace terrain::runtime {

/// `lodDepth`: the frame's depth (reversed Z, rows bottom-up, the camera's viewport);
/// `lodDepthNoSkirts`: the same frame without skirts (empty: every drawn pixel is surface).
ScreenSpaceErrorStats measureGlobeScreenSpaceError(const Camera& camera,
                                                   std::span<const float> lodDepth,
                                                   std::span<const float> lodDepthNoSkirts,
                                                   const io::GlobeSourceSurface& surface,
                                                   double thresholdPx);

}  // namespace terrain::runtime
