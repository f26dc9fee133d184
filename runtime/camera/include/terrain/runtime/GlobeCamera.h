// GlobeCamera: a Camera placed on the WGS84 globe in geodetic terms (DESIGN.md, "The globe"):
// latitude, longitude and height above the ellipsoid, heading (clockwise from north) and
// pitch (up from the horizon). The camera's position is ECEF in double; its frame is the
// ellipsoid's east-north-up there, so yaw and pitch keep their planar meaning.
#pragma once

#include "terrain/globe/Wgs84.h"
#include "terrain/runtime/Camera.h"

#include <glm/mat3x3.hpp>

namespace terrain::runtime {

struct GlobePose {
    globe::Geodetic where;
    double headingDeg = 0.0;  ///< 0 north, 90 east
    double pitchDeg = -90.0;  ///< −90 straight down, 0 at the horizon
};

/// East, north and up at a latitude and longitude, as the columns of a matrix.
glm::dmat3 eastNorthUp(double latitudeDeg, double longitudeDeg);

/// The near plane on a globe, fixed: reversed-Z float depth resolves the same relative
/// distance (about 1e-7) at every range whatever the near plane, so one small enough for a
/// camera 1 m above the ground serves orbit too. (A near plane from the height above the
/// ellipsoid would clip the ground in front of a camera on a 4 km peak.)
inline constexpr double kGlobeNearPlaneM = 0.1;

/// Sets the camera's position, frame, yaw and pitch from `pose`, and the near plane.
void placeOnGlobe(Camera& camera, const GlobePose& pose);

/// The pose a camera has (its frame need not be the one at its position).
GlobePose globePoseOf(const Camera& camera);

}  // namespace terrain::runtime
