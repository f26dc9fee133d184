#include "ViewControls.h"

#include "terrain/runtime/Surface.h"

namespace terrain::view {

std::unique_ptr<ViewControls> ViewControls::create(const runtime::TerrainSession& session,
                                                   const ViewerOptions& options) {
    if (session.surface().kind() == runtime::SurfaceKind::Globe)
        return makeGlobeControls(session, options);
    return makePlaneControls(session, options);
}

}  // namespace terrain::view
