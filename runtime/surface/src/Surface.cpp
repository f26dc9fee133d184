// Surface: what both surfaces share: names, the view's frustum, the horizon test, and the
// choice of surface by the manifest.
#include "terrain/runtime/Surface.h"

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

std::unique_ptr<Surface> makeSurface(const io::PyramidManifest& manifest) {
    if (manifest.globe) return std::make_unique<GlobeSurface>(manifest);
    return std::make_unique<PlaneSurface>(manifest);
}

}  // namespace terrain::runtime
