// SkirtDepth: one pass for the bound, one to hand it to every draw.
#include "terrain/runtime/SkirtDepth.h"

#include "terrain/base/Assert.h"

#include <algorithm>
#include <optional>

namespace terrain::runtime {

void assignSkirtDepths(std::span<PatchDraw> draws, const cache::GpuTilePool& pool) {
    float depthM = 0.0f;
    for (const PatchDraw& draw : draws) {
        float blockErrorM =
            *std::max_element(draw.bareBlockErrorsM.begin(), draw.bareBlockErrorsM.end());
        if (draw.ownsTile()) {
            const std::optional<float> resident = pool.maxBlockErrorM(draw.id);
            TERRAIN_ASSERT(resident.has_value(), "assignSkirtDepths: a draw is not resident");
            // Plus what its instance adds to its tile's λ (a native tile's bulge; 0 otherwise).
            blockErrorM += *resident;
        }
        depthM = std::max(depthM, draw.errorM + blockErrorM + draw.seamGapM);
    }
    for (PatchDraw& draw : draws) draw.skirtDepthM = depthM;
}

}  // namespace terrain::runtime
