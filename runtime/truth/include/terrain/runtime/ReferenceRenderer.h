// ReferenceRenderer: ground truth images for the accuracy measures (DESIGN.md, "Measurement
// is part of the product"; docs/accuracy.md, docs/globe.md): draws a ReferenceScene — the
// full-resolution surface, every sample of the truth a vertex, no LOD — for a camera, with
// the LOD draw's placement and shading (the frame block, terrain_shading.glsl), into a
// framebuffer with a colour, a depth and a world-height target
// (gl::Framebuffer::createWithFloatAttachment). One renderer for either surface: the scene
// says what to draw (PlaneReferenceScene.h, GlobeReferenceScene.h), one ReferenceBatch draws
// it.
//
// It shares no LOD code: no quadtree, no tessellation, no error bounds. Slow on purpose: it
// must be right, not fast.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/FrameBlock.h"
#include "terrain/runtime/ReferenceBatch.h"
#include "terrain/runtime/ReferenceScene.h"

#include <array>
#include <cstdint>
#include <memory>

namespace terrain::runtime {

/// The parts of the terrain's look that do not depend on geometry (TerrainStyle's).
struct ReferenceStyle {
    std::array<float, 3> skyColor{0.72f, 0.80f, 0.90f};  ///< fog colour
    float fogDensityPerM = 0.0f;                         ///< 0: no fog
};

struct ReferenceDrawStats {
    std::uint64_t tiles = 0;      ///< instances drawn: the plane's tiles, the globe's regions
    std::uint64_t triangles = 0;  ///< 2 per cell of every drawn instance
    int batches = 0;              ///< instanced draws
    /// False when the draw stopped at its limit (maxRegions): the image is partial and must
    /// not be compared.
    bool complete = true;
};

/// Render thread only; draws into the framebuffer bound by the caller. Holds its own GL
/// objects; the depth test, reversed-Z clip control and program state it sets are put back
/// to GL's defaults after each draw.
class ReferenceRenderer {
public:
    /// The most regions one draw of a scene that walks them takes (the globe's: 655 million
    /// triangles of 129-sample patches): a planet of fine data seen whole from orbit would
    /// take hours on a CPU rasteriser.
    static constexpr std::uint64_t kDefaultMaxRegions = 20000;

    /// The renderer of `scene`. Errors: the program does not build.
    static Result<ReferenceRenderer> create(std::unique_ptr<ReferenceScene> scene);

    /// Draws the scene in `camera`'s frustum: colour at location 0, world height (metres) at
    /// location 1. Depth must be cleared to 0 (reversed Z), as for the LOD draw. Errors (a
    /// patch that cannot be read) name the shard file and the patch. Past `maxRegions`
    /// regions (a scene that walks them) it stops, and ReferenceDrawStats::complete is false.
    Result<ReferenceDrawStats> draw(const Camera& camera, const ReferenceStyle& style,
                                    std::uint64_t maxRegions = kDefaultMaxRegions);

    ReferenceScene& scene() { return *m_scene; }

private:
    std::unique_ptr<ReferenceScene> m_scene;
    ReferenceBatch m_batch;
    FrameBlockBuffer m_frame;
};

}  // namespace terrain::runtime
