#include "ViewControls.h"

#include "GlobeControls.h"
#include "PlaneControls.h"

#include "terrain/runtime/Surface.h"

namespace terrain::view {

std::unique_ptr<ViewControls> ViewControls::create(const runtime::TerrainSession& session,
                                                   const ViewerOptions& options) {
    if (session.surface().kind() == runtime::SurfaceKind::Globe)
        return std::make_unique<GlobeControls>(session, options);
    return std::make_unique<PlaneControls>(session, options);
}

}  // namespace terrain::view
