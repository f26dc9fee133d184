// writePatchInstanceRecords: double → float only after subtracting the anchor.
#include "terrain/runtime/PatchInstanceRecord.h"

#include "terrain/base/Assert.h"

namespace terrain::runtime {

void writePatchInstanceRecords(const io::PyramidLayout& layout, const cache::GpuTilePool& pool,
                               std::span<const PatchDraw> patches, glm::dvec2 anchor,
                               std::vector<PatchInstanceRecord>& out) {
    out.clear();
    for (const PatchDraw& p : patches) {
        TERRAIN_ASSERT(pool.isResident(p.id) && pool.layerOf(p.id) == p.layer,
                       "drawing a patch that is not resident on its layer");
        const io::PatchInfo& info = *pool.info(p.id);
        const std::int64_t step = layout.levelStep(p.id.level);
        const double originX = static_cast<double>(layout.patchOriginX(p.id) * step) - anchor.x;
        const double originY = static_cast<double>(layout.patchOriginY(p.id) * step) - anchor.y;
        out.push_back({{static_cast<float>(originX), static_cast<float>(originY),
                        static_cast<float>(step), 0.0f},
                       {p.errorM, p.skirtDepthM, info.minHeight, info.maxHeight},
                       {p.layer, p.id.level, static_cast<std::int32_t>(p.id.x),
                        static_cast<std::int32_t>(p.id.y)},
                       {0.0f, 0.0f, 0.0f, 0.0f}});
    }
}

}  // namespace terrain::runtime
