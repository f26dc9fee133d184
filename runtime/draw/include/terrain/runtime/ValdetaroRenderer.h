// ValdetaroRenderer: the draw of Valdetaro et al. 2011 (LodMethod::Valdetaro2011): the
// patches the LOD selects (the finest level, a flat grid with no hierarchy once streaming
// settles), each cut into the paper's tiles, drawn in one instanced draw of GL_PATCHES whose
// control stage (shaders/valdetaro.tesc) sets every tile's factors from its own reference
// points, HAM_max and screen error (§5), and whose evaluation stage displaces the vertices
// from the GPU tile pool's heights (§6.3). The per-tile texture of §6.2 comes from
// ValdetaroTiles, computed once. No skirts (the paper has none).
#pragma once

#include "terrain/base/Result.h"
#include "terrain/cache/GpuTilePool.h"
#include "terrain/gl/Texture.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/MethodPatchDraw.h"
#include "terrain/runtime/PatchRenderer.h"
#include "terrain/runtime/PatchSelection.h"
#include "terrain/runtime/TerrainGeometry.h"
#include "terrain/runtime/TerrainRenderer.h"
#include "terrain/runtime/ValdetaroTiles.h"

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace terrain::runtime {

/// The paper's free parameters (§5.1, §5.3); ε̂ is the draw's errorPx.
struct ValdetaroParameters {
    /// g(HAM) = gain · √HAM_max (§5.1: "a logarithmic function or the square root").
    double hamGain = 1.0;
    /// d_max, the distance within which a tile gets T_max (§5.3), as pixels one DEM sample
    /// spans there: d_max = γ · spacing / pixelsPerSample (γ: Camera::errorScale). At 1,
    /// one quad a sample is one pixel where T_max starts to fall.
    double pixelsPerSampleAtDMax = 1.0;
};

/// Render thread only; draws into the framebuffer bound by the caller.
class ValdetaroRenderer final : public PatchRenderer {
public:
    static Result<ValdetaroRenderer> create(const io::PyramidLayout& layout, int maxInstances,
                                            const ValdetaroTileGrid& tiles,
                                            const ValdetaroParameters& parameters = {});

    /// Draws `patches` (resident in `pool`) seen by `camera`, each as its tiles, at ε̂ =
    /// errorPx. Depth cleared to 0 (reversed Z). Shaded or debug views as the style
    /// says; style.skirts and fixedTessFactor do not apply.
    TerrainDrawStats draw(const Camera& camera, const TerrainGeometry& geometry,
                          const cache::GpuTilePool& pool, std::span<const PatchDraw> patches,
                          const TerrainStyle& style, double errorPx) override;

    const ValdetaroParameters& parameters() const { return m_parameters; }

private:
    MethodPatchDraw m_draw;  // layerLevel.zw of its records: the patch's x, y
    gl::Texture m_tiles;
    ValdetaroParameters m_parameters;
    int m_tilesPerPatch = 0;
    int m_tileQuads = 0;
};

}  // namespace terrain::runtime
