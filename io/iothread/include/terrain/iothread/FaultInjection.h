// FaultInjection: makes the streaming I/O thread slow and unreliable on purpose, so tests
// and flights can show that missing or late tiles never make holes or crashes.
#pragma once

#include "terrain/pyramid/PyramidLayout.h"

#include <cstdint>

namespace terrain::io {

struct FaultInjection {
    double errorRate = 0.0;       ///< probability in [0, 1] that a patch read fails
    double addedLatencyMs = 0.0;  ///< added before every read
    std::uint64_t seed = 0;

    /// Whether a read of `id` fails: a pure function of (seed, id), like a bad sector, so
    /// the outcome does not depend on the order the I/O thread reads in and tests can
    /// predict it. The root (level 0) never fails by injection: it is the ancestor of last
    /// resort that draws wherever finer tiles are missing. Any thread.
    bool failsRead(const PatchId& id) const;
};

}  // namespace terrain::io
