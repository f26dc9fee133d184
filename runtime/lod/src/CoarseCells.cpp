// CoarseCells: every cell's projected bound, from the largest cell size down; a size fails
// at its first cell over ε.
#include "terrain/runtime/CoarseCells.h"

#include "terrain/pyramid/CoarseCellErrors.h"
#include "terrain/runtime/EdgeTessellation.h"

#include <algorithm>

namespace terrain::runtime {

CoarseCellChoice coarseCellChoice(const Camera& camera, const TerrainGeometry& geometry,
                                  const io::PatchId& id, const io::PatchInfo& info,
                                  std::span<const float> cellErrorsM, double errorPx) {
    if (cellErrorsM.empty()) return {};
    const io::PyramidLayout& layout = geometry.layout();
    const int blocks = layout.blocksPerSide();
    const int levels = io::coarseCellLevels(layout.patchQuads(), layout.blockQuads());
    // Heights widened by Err(P), as every edge's box is: an error's segment ends on the
    // full-resolution surface.
    const double patchErrorM = static_cast<double>(info.error);
    const double lowM = static_cast<double>(info.minHeight) - patchErrorM;
    const double highM = static_cast<double>(info.maxHeight) + patchErrorM;
    const glm::dmat4 viewProjection = camera.relativeViewProjection();
    const glm::dvec2 viewportPx{camera.viewportWidth, camera.viewportHeight};
    for (int k = levels; k >= 1; --k) {
        const int cellBlocks = 1 << k;
        const int cellsPerSide = blocks >> k;
        const std::span<const float> cells =
            cellErrorsM.subspan(static_cast<std::size_t>(io::coarseCellOffset(blocks, k)),
                                static_cast<std::size_t>(cellsPerSide * cellsPerSide));
        double largestM = 0.0;
        bool within = true;
        for (int cy = 0; cy < cellsPerSide && within; ++cy) {
            for (int cx = 0; cx < cellsPerSide && within; ++cx) {
                const double errorM =
                    static_cast<double>(cells[static_cast<std::size_t>(cy * cellsPerSide + cx)]) +
                    patchErrorM;
                const glm::ivec2 first{cx * cellBlocks, cy * cellBlocks};
                const Aabb world =
                    blocksWorldBox(geometry, id, first, first + (cellBlocks - 1), lowM, highM);
                const Aabb relative{.min = world.min - camera.position,
                                    .max = world.max - camera.position};
                within =
                    errorM * verticalErrorPxPerM(viewProjection, viewportPx, relative) < errorPx;
                largestM = std::max(largestM, errorM);
            }
        }
        if (within) return {.cellQuads = layout.blockQuads() << k, .errorM = largestM};
    }
    return {};
}

}  // namespace terrain::runtime
