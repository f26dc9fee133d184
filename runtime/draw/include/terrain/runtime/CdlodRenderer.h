// CdlodRenderer: the draw of CDLOD (Strugar 2009; LodMethod::Cdlod): every patch the LOD
// selects (LodQuadtree with SplitRule::ProjectedSpacing, its distance ranges) as one instance
// of a regular indexed grid of the patch's samples, morphed in the vertex stage towards the
// next coarser level's grid near the end of its range (shaders/cdlod.vert). No tessellation,
// no skirts: the morph closes the seams between levels.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/cache/GpuTilePool.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/MethodPatchDraw.h"
#include "terrain/runtime/PatchRenderer.h"
#include "terrain/runtime/PatchSelection.h"
#include "terrain/runtime/SampleGrid.h"
#include "terrain/runtime/TerrainGeometry.h"
#include "terrain/runtime/TerrainRenderer.h"

#include <span>
#include <vector>

namespace terrain::runtime {

/// Render thread only; draws into the framebuffer bound by the caller.
class CdlodRenderer final : public PatchRenderer {
public:
    /// Strugar's default: morphing starts two thirds of the way through a level's range.
    static constexpr float kMorphStartRatio = 0.66f;

    static Result<CdlodRenderer> create(const io::PyramidLayout& layout, int maxInstances);

    /// Draws `patches` (resident in `pool`) seen by `camera`, ranges from τ = errorPx
    /// (R_l = γ · s_l / τ). Depth cleared to 0 (reversed Z). style.skirts,
    /// fixedTessFactor and cullBlocks do not apply.
    TerrainDrawStats draw(const Camera& camera, const TerrainGeometry& geometry,
                          const cache::GpuTilePool& pool, std::span<const PatchDraw> patches,
                          const TerrainStyle& style, double errorPx) override;

private:
    MethodPatchDraw m_draw;  // its vertex array is unused: the grid's holds the indices
    SampleGrid m_grid;       // the patch's samples
    int m_gridQuads = 0;
};

}  // namespace terrain::runtime
