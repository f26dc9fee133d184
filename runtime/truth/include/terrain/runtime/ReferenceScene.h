// ReferenceScene: what the reference renderer (ReferenceRenderer.h) draws on one surface —
// every sample of the truth a vertex, no LOD — as instances of one grid in a ReferenceBatch:
// the plane's finest level cut into tiles (PlaneReferenceScene.h), the globe's finest data
// walked from the six face roots (GlobeReferenceScene.h). A scene says which vertex stage
// places its instances, fills the surface's part of the frame block (as the LOD draw's
// SurfacePlacement does, so both draws place and shade alike) and adds the instances in a
// camera's view.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/FrameBlock.h"
#include "terrain/runtime/ReferenceBatch.h"

#include <cstdint>
#include <string>

namespace terrain::runtime {

/// Render thread only.
class ReferenceScene {
public:
    virtual ~ReferenceScene() = default;

    /// The program's name and its vertex stage (shaders/reference.vert,
    /// shaders/globe_reference.vert); the fragment stage is reference.frag.
    virtual std::string name() const = 0;
    virtual std::string vertexStage() const = 0;
    /// Whether the surface is the globe (reference.frag then filters its normals with the
    /// globe's surface functions, TERRAIN_SURFACE_GLOBE) or the plane.
    virtual bool globe() const = 0;
    /// Quads a side of the grid each instance draws, and samples a side of its tile.
    virtual int gridQuads() const = 0;
    virtual int tileSamples() const = 0;

    /// Fills the surface's part of `block` for `camera`.
    virtual void beginFrame(const Camera& camera, FrameBlock& block) = 0;

    /// Adds every instance in `camera`'s view to `batch` (which draws them as it fills).
    /// Returns false when it stopped past `maxRegions` regions walked (a scene that walks
    /// regions: the globe's), leaving the image partial. Errors (a patch that cannot be
    /// read) name the shard file and the patch.
    virtual Result<bool> addInstances(const Camera& camera, ReferenceBatch& batch,
                                      std::uint64_t maxRegions) = 0;
};

}  // namespace terrain::runtime
