// GlobeKit: the globe's flight, which SurfaceKit's globe side flies (GlobeKit.cpp) and
// terrain-bench too: the default flight from 20,000 km straight down to `clearanceM` above the
// ground at the centre of the data (the finest source's extent, the ground read from the
// pyramid's finest patch there, io::GlobeGroundQuery).
#pragma once

#include "terrain/base/Result.h"
#include "terrain/runtime/GlobeCameraPath.h"

#include <filesystem>

namespace terrain::tools {

struct GlobeFlightTarget {
    double latitudeDeg = 0.0;
    double longitudeDeg = 0.0;
    double groundM = 0.0;  ///< the drawn ground there, above the ellipsoid
    int groundLevel = -1;  ///< the face level it was read at; −1: no data there
};

/// The clearance of the default flight's end above the ground.
inline constexpr double kArrivalClearanceM = 1.0;

/// The centre of the data and the ground there. Errors name the pyramid.
Result<GlobeFlightTarget> globeFlightTarget(const std::filesystem::path& pyramid);

/// GlobeCameraPath::fromOrbit over globeFlightTarget, `durationS` long, ending `clearanceM`
/// above its ground.
Result<runtime::GlobeCameraPath> globeOrbitFlight(const std::filesystem::path& pyramid,
                                                  double durationS,
                                                  double clearanceM = kArrivalClearanceM);

}  // namespace terrain::tools
