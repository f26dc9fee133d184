// BuildClock: how the builders time their phases and themselves (PyramidBuildSummary's
// seconds, the manifest's build.seconds).
#pragma once

#include <chrono>

namespace terrain::io {

using BuildClock = std::chrono::steady_clock;

inline double secondsSince(BuildClock::time_point start) {
    return std::chrono::duration<double>(BuildClock::now() - start).count();
}

}  // namespace terrain::io
