// PlaneFrame: the frame block (FrameBlock.h) of the draws over the plane that TerrainRenderer
// does not issue, the comparison methods' own meshes (the RTIN yardstick, Lee & Shin,
// Ripolles et al.), whose stages read u_frame as the patch draws do: the camera, the plane's
// anchor frame (PlanePlacement) and the look, in one uniform buffer.
#pragma once

#include "terrain/runtime/Camera.h"
#include "terrain/runtime/FrameBlock.h"
#include "terrain/runtime/SurfacePlacement.h"
#include "terrain/runtime/TerrainGeometry.h"
#include "terrain/runtime/TerrainStyle.h"

#include <glm/vec2.hpp>

#include <string>

namespace terrain::runtime {

/// Render thread only; `geometry` must outlive it.
class PlaneFrame {
public:
    PlaneFrame(const TerrainGeometry& geometry, const std::string& label);

    /// Fills the block for `camera` (its frame and ε, the plane's anchor frame, `style`'s
    /// look), uploads it and binds it at TERRAIN_BINDING_FRAME_BLOCK for the passes that
    /// follow. Returns the anchor: the DEM sample at or before the camera, which the stages'
    /// positions are relative to.
    glm::dvec2 bind(const Camera& camera, const TerrainStyle& style, double errorPx);
    /// Unbinds the block (after the passes that read it).
    static void unbind();

private:
    PlanePlacement m_placement;
    FrameBlockBuffer m_buffer;
};

}  // namespace terrain::runtime
