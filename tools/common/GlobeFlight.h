// GlobeFlight: the camera path a tool flies over a globe pyramid: a globe camera path file
// (docs/camera-path.md, "Globe camera paths"), or the default flight from 20,000 km straight
// down to `clearanceM` above the ground at the centre of the data (the finest source's extent),
// the ground read from the pyramid's finest patch there (io::GlobeGroundQuery).
#pragma once

#include "terrain/base/Result.h"
#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/runtime/GlobeCameraPath.h"

#include <filesystem>
#include <string>

namespace terrain::tools {

struct GlobeFlightTarget {
    double latitudeDeg = 0.0;
    double longitudeDeg = 0.0;
    double groundM = 0.0;  ///< the drawn ground there, above the ellipsoid
    int groundLevel = -1;  ///< the face level it was read at; −1: no data there
};

/// The centre of the data and the ground there. Errors name the pyramid.
Result<GlobeFlightTarget> globeFlightTarget(const std::filesystem::path& pyramid);

/// `pathFile` loaded when not empty, else GlobeCameraPath::fromOrbit over globeFlightTarget,
/// ending `clearanceM` above its ground, `durationS` long.
Result<runtime::GlobeCameraPath> globeFlight(const std::filesystem::path& pyramid,
                                             const std::string& pathFile, double durationS,
                                             double clearanceM = 1.0);

}  // namespace terrain::tools
