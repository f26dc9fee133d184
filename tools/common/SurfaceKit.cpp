// SurfaceKit: the kit of a surface, and the refusals both surfaces word alike.
#include "SurfaceKit.h"

namespace terrain::tools {

std::unique_ptr<SurfaceKit> SurfaceKit::of(runtime::SurfaceKind kind) {
    return kind == runtime::SurfaceKind::Globe ? makeGlobeKit() : makePlaneKit();
}

std::unique_ptr<SurfaceKit> SurfaceKit::of(const io::PyramidManifest& manifest) {
    return of(manifest.globe ? runtime::SurfaceKind::Globe : runtime::SurfaceKind::Plane);
}

Status SurfaceKit::supports(const std::string& pyramid, runtime::LodMethod method) const {
    if (Status supported = runtime::lodMethodSupports(method, kind()); !supported)
        return Error{pyramid + ": a " + std::string(tiling()) +
                     " pyramid: " + supported.error().message};
    return {};
}

void SurfaceKit::applyLook(runtime::TerrainStyle& style, const DrawStyleFlags& look,
                           const runtime::Surface& surface) const {
    style.wireframe = look.wireframe;
    style.skirts = !look.noSkirts;
    style.debugView = look.debugViewValue();
    look.applyImagery(style);
    skyAndFog(style, look, surface);
}

Status SurfaceKit::refuseForeignFlags(const std::string& pyramid, const GlobeFlags& globe) const {
    if (kind() == runtime::SurfaceKind::Globe) return {};
    const std::vector<std::string> given = globe.given();
    if (given.empty()) return {};
    std::string names;
    for (const std::string& name : given) names += (names.empty() ? "" : ", ") + name;
    return Error{pyramid + ": a planar pyramid; " + names + (given.size() == 1 ? " is" : " are") +
                 " for globe pyramids only"};
}

}  // namespace terrain::tools
