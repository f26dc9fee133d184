// TerrainRenderer: draws the selected patches from the GPU tile pool in ONE instanced
// draw of GL_PATCHES (Yusov & Shevtsov 2011, §5 "Implementation Details"), on the plane or
// on the globe: one instance per patch; per instance one quad patch primitive per
// tessellation block, whose edge factors the control stage picks from the block errors (§5
// "Fine-Grain Level of Detail Selection"; CPU reference EdgeTessellation.h), and the patch's
// skirts (§5, after Ulrich). Heights and block errors come from the patch's texture-array
// layers; per-instance records (PatchInstance, written by the surface's SurfacePlacement)
// live in a storage buffer and the frame's parameters in one uniform block (FrameBlock),
// both written once a frame. The program is built for the surface (shaders/terrain.*).
#pragma once

#include "terrain/base/Result.h"
#include "terrain/cache/GpuTilePool.h"
#include "terrain/gl/Buffer.h"
#include "terrain/gl/Program.h"
#include "terrain/gl/Query.h"
#include "terrain/gl/Texture.h"
#include "terrain/gl/VertexArray.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/FrameBlock.h"
#include "terrain/runtime/ImagerySelection.h"
#include "terrain/runtime/PatchDraw.h"
#include "terrain/runtime/PatchInstance.h"
#include "terrain/runtime/ShadingTiles.h"
#include "terrain/runtime/Surface.h"
#include "terrain/runtime/SurfacePlacement.h"
#include "terrain/runtime/TerrainStyle.h"

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

namespace terrain::runtime {

struct TerrainRendererOptions {
    /// Builds the program with TERRAIN_DEBUG_TESS_FACTORS: the control stage also writes
    /// the factors of every (instance, primitive) to a buffer readTessFactors() returns.
    /// For tests.
    bool recordTessFactors = false;
    /// Shades with the normal of the patch's full-resolution mesh at each fragment
    /// (terrain.frag, TERRAIN_FRAGMENT_NORMALS), so shading does not change when the
    /// tessellation does; false: normals interpolated between the drawn vertices, as Yusov's
    /// draw has them, for comparisons.
    bool fragmentNormals = true;
    /// Also builds the program variant a style with imageryTexelsPerPixel draws with
    /// (TERRAIN_IMAGERY_TEXELS_PER_PIXEL: terrain.frag writes the draped imagery's texels per
    /// pixel at output 1). The normal draw is unchanged either way. For measures.
    bool imageryTexelsPerPixel = false;
};

/// What the control stage chose for one primitive (recordTessFactors only).
struct RecordedTessFactors {
    static constexpr std::int32_t kSkirt = 1;   ///< flags: the primitive is a skirt
    static constexpr std::int32_t kCulled = 2;  ///< flags: discarded, outside the frustum
    /// flags: discarded, its area drawn by its patch's coarse cell (then outer and inner are
    /// 0); the cell itself is recorded at the cell's north-west block and its first skirt
    static constexpr std::int32_t kMerged = 4;

    /// GL order: west (u = 0), north, east, south; the factors chosen before culling (a
    /// culled primitive's levels are all 0).
    std::array<std::int32_t, 4> outer{};
    std::array<std::int32_t, 2> inner{};
    std::int32_t flags = 0;
    float skirtDropM = 0.0f;  ///< skirts: Λ_ec(d) + the instance's skirt depth

    bool isSkirt() const { return (flags & kSkirt) != 0; }
    bool culled() const { return (flags & kCulled) != 0; }
    bool merged() const { return (flags & kMerged) != 0; }
};
static_assert(sizeof(RecordedTessFactors) == 32);  // std430 TessFactorRecord, terrain.tesc

/// The imagery a draw drapes (issue 47): the frame's selection, made for the same patches in
/// the same order, and the texture array its nodes' layers index.
struct DrapedImagery {
    const ImagerySelection& selection;
    const gl::Texture& tiles;
    /// The anisotropy `tiles`' sampler filters with: the fragment stage picks a tile whose
    /// texels match the footprint's short side only as far as the sampler covers its long one.
    float maxAnisotropy = 1.0f;
};

/// Render thread only; draws into the framebuffer bound by the caller. Holds its own GL
/// objects; the depth test, reversed-Z clip control, polygon mode and program state it
/// sets are put back to GL's defaults after each draw.
class TerrainRenderer {
public:
    /// For pyramids of `surface` (which must outlive the renderer); `maxInstances` bounds the
    /// patches of one draw (the pool's capacity, and room for bare patches on the globe).
    static Result<TerrainRenderer> create(const Surface& surface, int maxInstances,
                                          const TerrainRendererOptions& options = {});

    /// Draws `patches` (every patch with a tile resident in `pool` on its layer,
    /// TERRAIN_ASSERT) seen by `camera` at ε = `errorPx`: prepare() then submit(). Depth must
    /// be cleared to 0 (reversed Z). Give the patches their skirt depth first
    /// (assignSkirtDepths, SkirtDepth.h), or skirts may be short.
    /// With `imagery` (and style.imagery, in the shaded view) the patches wear its layers.
    TerrainDrawStats draw(const Camera& camera, const cache::GpuTilePool& pool,
                          std::span<const PatchDraw> patches, const TerrainStyle& style,
                          double errorPx, const DrapedImagery* imagery = nullptr);

    /// The CPU half of draw(): writes the instance records (camera-relative, from double)
    /// and the frame block into their buffers. Allocates nothing.
    void prepare(const Camera& camera, const cache::GpuTilePool& pool,
                 std::span<const PatchDraw> patches, const TerrainStyle& style, double errorPx,
                 const DrapedImagery* imagery = nullptr);
    /// The GL half: binds the pool's textures and issues the one instanced draw of what
    /// prepare() wrote. (Drivers may allocate inside the draw call: Mesa's tessellator does.)
    TerrainDrawStats submit(const cache::GpuTilePool& pool);

    /// recordTessFactors only: the records of the last draw, (instance · (K² + 4K) +
    /// primitive) for K = blocksPerSide (skirt records exist only if it drew skirts).
    /// Waits for the GPU.
    std::vector<RecordedTessFactors> readTessFactors(int instances) const;

private:
    /// Quad patch primitives per instance: blocksPerSide² blocks, then 4 · blocksPerSide
    /// skirts when the style has them.
    int primitivesPerInstance(bool skirts) const;
    /// Uploads the selection's lists; the number of layers the frame draws.
    int prepareImagery(const DrapedImagery& imagery, std::size_t patches,
                       const TerrainStyle& style);

    const Surface* m_surface = nullptr;
    std::unique_ptr<SurfacePlacement> m_placement;
    gl::Program m_program;
    gl::Program m_texelsPerPixelProgram;  // options.imageryTexelsPerPixel only
    gl::VertexArray m_vertexArray;
    gl::Buffer m_instances;
    gl::Buffer m_shadingTiles;  // kShadingAncestors per instance (ShadingTiles.h)
    // The imagery selection's lists (ImagerySelection.h), grown as frames need, and the
    // texture array the prepared frame samples (null: no imagery).
    gl::Buffer m_imageryRoots;
    gl::Buffer m_imageryNodes;
    gl::Buffer m_imageryChildren;
    const gl::Texture* m_imageryTiles = nullptr;
    FrameBlockBuffer m_frameBuffer;
    gl::Buffer m_tessFactors;  // recordTessFactors only
    gl::Query m_primitivesQuery;
    gl::Query m_timeQuery;
    std::vector<PatchInstance> m_staging;  // capacity maxInstances
    std::vector<ShadingTile> m_shadingStaging;  // capacity maxInstances · kShadingAncestors
    FrameBlock m_frame;
    int m_maxInstances = 0;
    int m_preparedInstances = 0;
    int m_blocksPerSide = 0;
    int m_blockQuads = 0;
    bool m_skirts = true;
    bool m_wireframe = false;
    bool m_measure = false;
    bool m_texelsPerPixel = false;  // the prepared frame draws with m_texelsPerPixelProgram
};

}  // namespace terrain::runtime
