// BuildClock: how the builders time their phases (BuildSummary's seconds).
#pragma once

#include <chrono>

namespace terrain::io {

inline double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace terrain::io
