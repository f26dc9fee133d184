// PatchRenderer: how a comparison LOD method draws the patches its quadtree selected from the
// GPU tile pool (ValdetaroRenderer, LivnyRenderer, CdlodRenderer), so TerrainSession holds
// one of them whatever the method. (TerrainRenderer, the runtime's own draw, has more to
// offer — recorded factors, prepare/submit — and is held on its own.)
#pragma once

#include "terrain/cache/GpuTilePool.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/PatchSelection.h"
#include "terrain/runtime/TerrainGeometry.h"
#include "terrain/runtime/TerrainRenderer.h"

#include <span>

namespace terrain::runtime {

class PatchRenderer {
public:
    virtual ~PatchRenderer() = default;
    /// Draws `patches` (resident in `pool`) seen by `camera` into the bound framebuffer,
    /// depth cleared to 0 (reversed Z), at the method's threshold errorPx.
    virtual TerrainDrawStats draw(const Camera& camera, const TerrainGeometry& geometry,
                                  const cache::GpuTilePool& pool,
                                  std::span<const PatchDraw> patches, const TerrainStyle& style,
                                  double errorPx) = 0;
};

}  // namespace terrain::runtime
