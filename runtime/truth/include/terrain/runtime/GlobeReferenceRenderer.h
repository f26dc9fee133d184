// GlobeReferenceRenderer: ground truth images on the globe (DESIGN.md, "Measurement is part
// of the product"; docs/globe.md), the globe's ReferenceRenderer: draws a globe pyramid's
// finest data everywhere in view, every sample a vertex, no LOD, with the globe draw's
// placement (globe_patches.glsl) and shading (terrain_shading.glsl), into a framebuffer with
// a colour, a depth and a world-height target (gl::Framebuffer::createWithFloatAttachment).
//
// It shares no LOD code: no tessellation, no error bounds, no screen-space error of the data.
// It walks the pyramid on disk from the six face roots: into every present child, and where a
// child is absent it draws that quadrant from its parent's tile (bilinear between the tile's
// samples, as the LOD's virtual patches); a patch with no children is drawn sample for
// sample. Each such region is a grid of patchQuads² cells, each cell split along its
// north-west–south-east diagonal, and is split into four only where the ellipsoid's bulge
// over its flat cells would show on screen (more than kCurvatureTolerancePx): coarse data
// seen from close by is still drawn on the curved surface. Where data of different levels
// meet (a source's edge) the coarser side's edge is interpolated: without skirts a sliver of
// background can show there, in the reference alone. Slow on purpose: it must be right, not
// fast.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/gl/Buffer.h"
#include "terrain/gl/Program.h"
#include "terrain/gl/Texture.h"
#include "terrain/globe/GlobePatch.h"
#include "terrain/pyramid/PyramidReader.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/PatchInstance.h"
#include "terrain/runtime/ReferenceRenderer.h"
#include "terrain/runtime/SampleGrid.h"

#include <array>
#include <cstdint>
#include <map>
#include <vector>

namespace terrain::runtime {

/// Render thread only; draws into the framebuffer bound by the caller. Holds its own GL
/// objects; the depth state and program it sets are put back after each draw.
class GlobeReferenceRenderer {
public:
    static constexpr int kBatchRegions = 32;
    /// A region is split until its flat cells fall under the ellipsoid by at most this on
    /// screen: a twentieth of the measures' 0.05 px tolerance would be below float depth.
    static constexpr double kCurvatureTolerancePx = 0.05;
    /// The finest level a region is split to for curvature (a patch there is ~15 cm wide).
    static constexpr int kMaxRegionLevel = 24;
    /// The most regions one draw takes (655 million triangles of 129-sample patches): a planet
    /// of fine data seen whole from orbit would take hours on a CPU rasteriser.
    static constexpr std::uint64_t kDefaultMaxRegions = 20000;

    /// For globe pyramids of `manifest` (manifest.globe set).
    static Result<GlobeReferenceRenderer> create(const io::PyramidManifest& manifest);

    /// Draws the finest data in `camera`'s frustum: colour at location 0, world height
    /// (metres) at location 1. Depth must be cleared to 0 (reversed Z). ReferenceDrawStats'
    /// tiles are the regions drawn. Errors (a patch that cannot be read) name the shard file
    /// and the patch. Past `maxRegions` regions (drawn or walked through) it stops, and
    /// ReferenceDrawStats::complete is false.
    Result<ReferenceDrawStats> draw(const Camera& camera, io::PyramidReader& pyramid,
                                    const ReferenceStyle& style,
                                    std::uint64_t maxRegions = kDefaultMaxRegions);

private:
    // A patch-sized grid drawn from the tile of `tileId`: patch sample s lies on tile
    // sample texelOffset + s · texelStep.
    struct Region {
        globe::GlobePatchId id;
        globe::GlobePatchId tileId;
        double texelOffsetX = 0.0, texelOffsetY = 0.0, texelStep = 1.0;
        float minHeight = 0.0f, maxHeight = 0.0f;
        bool bare = false;  // a face no source covers: the ellipsoid, no tile
    };

    Status visitPatch(const globe::GlobePatchId& id, const io::PatchInfo& info);
    Status visitRegion(const Region& region);
    bool withinLimit();  // counts one more patch or region; false past m_maxRegions
    Status addRegion(const Region& region);
    Result<const io::PatchRecord*> tileOf(const globe::GlobePatchId& id);
    void submitBatch();

    gl::Program m_program;
    SampleGrid m_grid;
    gl::Buffer m_instances;
    gl::Texture m_heights;  // kBatchRegions layers of tileSamples²
    io::PyramidLayout m_layout;
    std::array<float, 2> m_heightRange{0.0f, 1.0f};

    // Per draw.
    io::PyramidReader* m_pyramid = nullptr;
    const Camera* m_camera = nullptr;
    Frustum m_frustum;
    std::uint64_t m_maxRegions = kDefaultMaxRegions;
    std::uint64_t m_visited = 0;  // patches and regions walked this draw
    double m_gamma = 1.0;
    glm::dvec3 m_cameraUp{0.0};
    std::vector<PatchInstance> m_staging;
    std::vector<std::uint64_t> m_layerTiles;           // the tile in each layer of this batch
    std::map<std::uint64_t, io::PatchRecord> m_tiles;  // read this draw, by layout patch
    ReferenceDrawStats m_stats;
};

}  // namespace terrain::runtime
