// ReferenceRenderer: ground truth for the accuracy measures (DESIGN.md, "Measurement is part
// of the product"): draws the full-resolution DEM — every sample of the pyramid's finest
// level a vertex, no LOD — for a camera, with the LOD draw's shading
// (terrain_shading.glsl), into a framebuffer with a colour, a depth and a world-height
// target (gl::Framebuffer::createWithFloatAttachment).
//
// It shares no LOD code: no quadtree, no tessellation, no error bounds. It draws the DEM's
// extent only (the finest level's last patches overhang it with clamped copies of its
// edge, which it discards). The finest level is cut into tiles of at most kMaxTileQuads quads a
// side; the tiles whose footprint and height range meet the view frustum are uploaded, kBatchTiles
// at a time, into a texture array and drawn as instances of one indexed grid (each cell split along
// its north-west– south-east diagonal, FullResolutionSurface::heightAt's referenceM). Slow on
// purpose: it must be right, not fast.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/gl/Buffer.h"
#include "terrain/gl/Program.h"
#include "terrain/gl/Texture.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/FullResolutionSurface.h"
#include "terrain/runtime/SampleGrid.h"

#include <array>
#include <cstdint>
#include <vector>

namespace terrain::runtime {

/// The parts of the terrain's look that do not depend on geometry (TerrainStyle's).
struct ReferenceStyle {
    std::array<float, 3> skyColor{0.72f, 0.80f, 0.90f};  ///< fog colour
    float fogDensityPerM = 0.0f;                         ///< 0: no fog
};

struct ReferenceDrawStats {
    std::uint64_t tiles = 0;      ///< tiles in the frustum, drawn
    std::uint64_t triangles = 0;  ///< 2 per cell of every drawn tile
    int batches = 0;              ///< instanced draws
    /// False when the draw stopped at its limit (GlobeReferenceRenderer's maxRegions): the
    /// image is partial and must not be compared.
    bool complete = true;
};

/// Render thread only; draws into the framebuffer bound by the caller. Holds its own GL
/// objects; the depth test, reversed-Z clip control and program state it sets are put back
/// to GL's defaults after each draw.
class ReferenceRenderer {
public:
    static constexpr int kMaxTileQuads = 128;
    static constexpr int kBatchTiles = 32;

    /// For pyramids of `layout` (its patch size sets the tile size).
    static Result<ReferenceRenderer> create(const io::PyramidLayout& layout);

    /// Draws every finest-level tile in `camera`'s frustum: colour at location 0, world
    /// height (metres) at location 1. Depth must be cleared to 0 (reversed Z), as for the
    /// LOD draw. Errors (a patch that cannot be read) name the shard file and the patch.
    Result<ReferenceDrawStats> draw(const Camera& camera, FullResolutionSurface& surface,
                                    const ReferenceStyle& style);

    int tileQuads() const { return m_tileQuads; }

private:
    // std430 ReferenceTile in reference.vert.
    struct alignas(16) TileInstance {
        std::array<float, 4> originLayer;
    };
    static_assert(sizeof(TileInstance) == 16);

    void submitBatch(int tiles);

    gl::Program m_program;
    SampleGrid m_grid;
    gl::Buffer m_instances;
    gl::Texture m_heights;  // kBatchTiles layers of (tileQuads + 3)² samples
    std::vector<TileInstance> m_staging;
    std::vector<float> m_tileScratch;
    int m_tileQuads = 0;
};

}  // namespace terrain::runtime
