// GlobeFlight: the camera path terrain-bench flies over a globe pyramid: a globe camera path
// file, or the default flight from orbit (GlobeKit.h).
#pragma once

#include "GlobeKit.h"

#include "terrain/base/Result.h"
#include "terrain/runtime/GlobeCameraPath.h"

#include <filesystem>
#include <string>

namespace terrain::tools {

/// `pathFile` loaded when not empty, else globeOrbitFlight, `durationS` long, ending
/// `clearanceM` above the ground at the data's centre.
inline Result<runtime::GlobeCameraPath> globeFlight(const std::filesystem::path& pyramid,
                                                    const std::string& pathFile, double durationS,
                                                    double clearanceM = kArrivalClearanceM) {
    if (!pathFile.empty()) return runtime::GlobeCameraPath::load(pathFile);
    return globeOrbitFlight(pyramid, durationS, clearanceM);
}

}  // namespace terrain::tools
