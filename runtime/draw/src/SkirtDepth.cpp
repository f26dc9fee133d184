// SkirtDepth: one pass for the bound, one to hand it to every draw.
#include "terrain/runtime/SkirtDepth.h"

#include "terrain/base/Assert.h"

#include <algorithm>
#include <optional>

namespace terrain::runtime {

void assignSkirtDepths(std::span<PatchDraw> draws, const cache::GpuTilePool& pool) {
    float depthM = 0.0f;
    for (const PatchDraw& draw : draws) {
        const std::optional<float> maybeBlockErrorM = pool.maxBlockErrorM(draw.id);
        TERRAIN_ASSERT(maybeBlockErrorM.has_value(), "assignSkirtDepths: a draw is not resident");
        depthM = std::max(depthM, draw.errorM + *maybeBlockErrorM);
    }
    for (PatchDraw& draw : draws) draw.skirtDepthM = depthM;
}

}  // namespace terrain::runtime
