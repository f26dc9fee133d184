// Peak and current resident memory of this process (VmHWM, VmRSS), for --json summaries and
// benchmarks.
#pragma once

#include <cstdint>

namespace terrain {

/// Bytes; 0 where /proc/self/status is not available.
std::uint64_t peakResidentBytes();

/// Resident memory now (VmRSS), bytes; 0 where /proc/self/status is not available.
/// Allocates (reads a file): sample it from time to time, not every frame.
std::uint64_t currentResidentBytes();

}  // namespace terrain
