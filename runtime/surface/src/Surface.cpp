// Surface: what both surfaces share: names, the view's frustum, the horizon test, and the
// choice of surface by the manifest.
#include "terrain/runtime/Surface.h"

#include "terrain/base/Assert.h"
#include "terrain/runtime/GlobeSurface.h"
#include "terrain/runtime/PlaneSurface.h"

namespace terrain::runtime {

std::string_view surfaceName(SurfaceKind kind) {
    return kind == SurfaceKind::Globe ? "globe" : "planar";
}

SurfaceView Surface::view(const Camera& camera) const {
    return {.camera = camera.position, .frustum = camera.frustum(), .horizon = std::nullopt};
}

bool Surface::belowHorizon(const SurfaceView& view, const PatchVolume& volume) const {
    const auto* box = std::get_if<globe::OrientedBox>(&volume);
    return view.horizon && box != nullptr && view.horizon->isHidden(*box);
}

PatchVolume Surface::nativeTileVolume(const io::PatchId& /*tile*/, float /*minHeight*/,
                                      float /*maxHeight*/,
                                      const globe::NativeWindow& /*window*/) const {
    TERRAIN_ASSERT(false, "a native tile on a surface without native grids");
    return Aabb{};
}

std::unique_ptr<Surface> makeSurface(const io::PyramidManifest& manifest,
                                     std::span<const io::NativeGridManifest> nativeGrids) {
    if (manifest.globe) return std::make_unique<GlobeSurface>(manifest, nativeGrids);
    return std::make_unique<PlaneSurface>(manifest);
}

}  // namespace terrain::runtime
