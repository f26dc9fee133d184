// Peak resident memory of this process (VmHWM), for --json summaries and benchmarks.
#pragma once

#include <cstdint>

namespace terrain::io {

/// Bytes; 0 where /proc/self/status is not available.
std::uint64_t peakResidentBytes();

}  // namespace terrain::io
