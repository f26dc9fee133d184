// CoarseCells: whether a drawn patch is tessellated as blocks (Yusov & Shevtsov 2011, §5) or,
// far enough away, as a grid of coarse cells of one quad each at factor 1
// (io/CoarseCellErrors.h says why and how the cells are bounded).
//
// A block costs at least two triangles whatever its error, so a distant patch of 16 × 16
// blocks of 8 quads costs at least 512 and its skirts 128 more, while its cells of 16 quads
// cost 128 and 64. The choice is the patch's: one cell size for all of it, so cells meet
// without T-junctions; neighbouring patches meet at skirts, as they do anyway. A patch takes
// the largest cell size at which every cell's Λ = bound + Err(P), projected over that cell's
// box (verticalErrorPxPerM, as the block edges are), stays below ε: the screen-space bound
// holds for every pixel of it, as it does for blocks.
#pragma once

#include "terrain/pyramid/PatchRecord.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/TerrainGeometry.h"

#include <span>

namespace terrain::runtime {

struct CoarseCellChoice {
    int cellQuads = 0;    ///< quads along a cell's side; 0: the patch is drawn as blocks
    double errorM = 0.0;  ///< Λ of the cells: their bound plus Err(P), metres (0 for blocks)
    bool coarse() const { return cellQuads > 0; }
};

/// The coarse cells of patch `id` (summary `info`, whose error is Err(P)) seen by `camera`
/// at ε = errorPx, given io::coarseCellErrors of its tile (`cellErrorsM`): the largest cell
/// size whose every cell's Λ projects below ε over its own box (the patch's height range
/// widened by Err(P)), or blocks.
CoarseCellChoice coarseCellChoice(const Camera& camera, const TerrainGeometry& geometry,
                                  const io::PatchId& id, const io::PatchInfo& info,
                                  std::span<const float> cellErrorsM, double errorPx);

}  // namespace terrain::runtime
