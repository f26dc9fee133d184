// Open file descriptors and threads of this process, for the stress test's check that a
// long run leaks neither (a shard left open, a thread started per request).
#pragma once

#include <cstdint>

namespace terrain {

/// Entries of /proc/self/fd (the descriptor used to list them not counted); 0 where /proc
/// is not available. Allocates: sample it from time to time, not every frame.
std::uint64_t openFileDescriptors();

/// Entries of /proc/self/task; 0 where /proc is not available.
std::uint64_t threadCount();

}  // namespace terrain
