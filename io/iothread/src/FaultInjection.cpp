// FaultInjection: the fault decision hashes (seed, patch) with SplitMix64.
#include "terrain/iothread/FaultInjection.h"

#include "terrain/source/SplitMix64.h"

namespace terrain::io {

bool FaultInjection::failsRead(const PatchId& id) const {
    if (errorRate <= 0.0 || id.level == 0) return false;
    std::uint64_t h = detail::mix64(seed ^ 0xA0761D6478BD642FULL);
    h = detail::mix64(h ^ static_cast<std::uint64_t>(id.level));
    h = detail::mix64(h ^ static_cast<std::uint64_t>(id.x));
    h = detail::mix64(h ^ static_cast<std::uint64_t>(id.y));
    const double u = static_cast<double>(h >> 11U) * 0x1.0p-53;  // uniform in [0, 1)
    return u < errorRate;
}

}  // namespace terrain::io
