// DriverWorkarounds: per-driver adjustments, keyed on the GL renderer string.
#include "terrain/runtime/DriverWorkarounds.h"

#include <malloc.h>

#include <limits>

namespace terrain::runtime {

DriverWorkaroundsApplied applyDriverWorkarounds(const GlInfo& info) {
    DriverWorkaroundsApplied applied;
    if (info.renderer.find("llvmpipe") != std::string::npos) {
        // 2 GiB, the most mallopt takes: more than a frame frees at the heap's top.
        applied.llvmpipeHeapTrimOff =
            mallopt(M_TRIM_THRESHOLD, std::numeric_limits<int>::max()) != 0;
    }
    return applied;
}

}  // namespace terrain::runtime
