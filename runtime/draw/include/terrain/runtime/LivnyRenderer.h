// LivnyRenderer: the draw of Livny et al. 2007 (LodMethod::Livny2007): every patch the LOD
// selects (LodQuadtree with SplitRule::LivnyEdges, Eq. 1) as four triangular tiles cut by its
// diagonals, each at its boundary edge's resolution, in one instanced draw of GL_PATCHES
// (shaders/livny.tesc and livny.tese say how, and where the tessellator replaces the paper's
// cached tile and strip meshes). No skirts: Claim 1 makes the patches meet without cracks.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/runtime/MethodPatchDraw.h"
#include "terrain/runtime/PatchRenderer.h"

namespace terrain::runtime {

/// Render thread only; draws into the framebuffer bound by the caller.
class LivnyRenderer final : public PatchRenderer {
public:
    static Result<LivnyRenderer> create(const io::PyramidLayout& layout, int maxInstances);

    /// Draws `patches` (resident in `pool`) seen by `camera` at τ = errorPx (Eq. 1's
    /// ρ = γ / (R_max · τ)). Depth cleared to 0 (reversed Z). style.skirts and
    /// fixedTessFactor do not apply.
    TerrainDrawStats draw(const Camera& camera, const TerrainGeometry& geometry,
                          const cache::GpuTilePool& pool, std::span<const PatchDraw> patches,
                          const TerrainStyle& style, double errorPx) override;

private:
    MethodPatchDraw m_draw;
    int m_patchQuads = 0;
};

}  // namespace terrain::runtime
