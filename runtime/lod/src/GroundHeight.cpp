// GroundHeight: walks the patch quadtree down the resident patches covering a point.
#include "terrain/runtime/GroundHeight.h"

#include <cmath>
#include <cstdint>

namespace terrain::runtime {

double conservativeGroundHeight(const TileResidency& residency, const TerrainGeometry& geometry,
                                double x, double y) {
    const io::PyramidLayout& layout = geometry.layout();
    const glm::dvec2 sample = geometry.sampleOfWorld(x, y);
    double height = geometry.maxHeight();
    if (!(sample.x >= 0.0 && sample.y >= 0.0)) return height;  // outside, or NaN
    for (int level = 0; level <= layout.finestLevel(); ++level) {
        const double patchSamples =
            static_cast<double>(layout.patchQuads()) * static_cast<double>(layout.levelStep(level));
        const io::PatchId id{level, static_cast<std::int64_t>(std::floor(sample.x / patchSamples)),
                             static_cast<std::int64_t>(std::floor(sample.y / patchSamples))};
        if (!layout.contains(id)) break;
        const io::PatchInfo* info = residency.residentInfo(id);
        if (info == nullptr) break;
        height = info->maxHeight;
    }
    return height;
}

}  // namespace terrain::runtime
