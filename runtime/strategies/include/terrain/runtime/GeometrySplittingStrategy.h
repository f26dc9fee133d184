// GeometrySplittingStrategy: Lee & Shin 2011, "Geometry splitting: an acceleration technique
// of quadtree-based terrain rendering using GPU", as a LodStrategy (LodMethod::Lee2011).
//
// Like the paper (§4: "our rendering process is using in-core method"), it holds the whole
// finest level on the GPU: the height field, the quadtree texture of roughness values
// (RoughnessQuadtree, built once when opened) and the split flags. Each frame the quadtree
// is built on the GPU from its root alone, by d passes of vertex splitting (§2.3) and up to
// d passes of triangle splitting against T-junctions (§2.4), then drawn with one indirect
// draw: the CPU sets uniforms and issues the passes, and reads back only the counters, to
// report them and to grow a list that overflowed (the frame is then built again).
//
// The paper's passes are geometry shaders feeding stream output; here they are compute
// passes appending to lists with atomic counters, each pass's dispatch arguments written by
// the GPU from the previous pass's counter (DrawAuto's role). Shaders: lee_*.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/gl/Buffer.h"
#include "terrain/gl/Program.h"
#include "terrain/gl/Query.h"
#include "terrain/gl/Texture.h"
#include "terrain/gl/VertexArray.h"
#include "terrain/runtime/LodStrategy.h"
#include "terrain/runtime/PlaneFrame.h"
#include "terrain/runtime/PlaneSurface.h"

#include <glm/vec2.hpp>

#include <array>
#include <filesystem>
#include <memory>
#include <vector>

namespace terrain::runtime {

class RoughnessQuadtree;

/// What the last frame's passes produced (read back from the GPU's counters).
struct GeometrySplittingCounts {
    std::uint64_t blocksEvaluated = 0;  ///< LOD flags computed (vertex-splitting inputs)
    std::uint64_t leaves = 0;           ///< blocks drawn
    std::uint64_t triangles = 0;        ///< triangles drawn
    int builds = 0;  ///< times the frame was built (more than 1 when a list overflowed)
};

class GeometrySplittingStrategy final : public LodStrategy {
public:
    /// GPU textures and lists plus the CPU arrays of the preprocessing together; a raster
    /// that needs more is refused before it is read.
    static constexpr std::size_t kDefaultMaxBytes = std::size_t{768} << 20;

    /// Reads the pyramid's finest level (planar only; errors name the pyramid) and builds
    /// the quadtree texture.
    static Result<std::unique_ptr<GeometrySplittingStrategy>> open(
        const std::filesystem::path& pyramid, double errorPx,
        std::size_t maxBytes = kDefaultMaxBytes);
    /// The same from a raster in memory (tests): width × height samples, rows running south.
    static Result<std::unique_ptr<GeometrySplittingStrategy>> create(
        const io::PyramidManifest& manifest, std::vector<float> heights, double errorPx,
        std::size_t maxBytes = kDefaultMaxBytes);
    ~GeometrySplittingStrategy() override;

    LodMethod method() const override { return LodMethod::Lee2011; }
    const Surface& surface() const override { return *m_surface; }
    /// τ, the tolerable screen-space error of Eq. 1–2.
    void setErrorPx(double errorPx) override { m_thresholdPx = errorPx; }
    double errorPx() const override { return m_thresholdPx; }

    const LodUpdateStats& beginFrame(const Camera& camera) override;
    /// Shaded only (style.debugView is ignored); no skirts.
    TerrainDrawStats draw(const Camera& camera, const TerrainStyle& style) override;
    void endFrame(FrameTelemetry& t) override;
    /// Wall time of the frame's GPU passes, counters read back included.
    double lodUpdateUs() const override { return m_lodUpdateUs; }

    bool settle(const Camera&, std::chrono::milliseconds) override { return true; }
    std::uint64_t loadsOutstanding() const override { return 0; }
    const TileFault* fatalFault() const override { return nullptr; }
    void drain(std::chrono::milliseconds) override {}
    /// The textures and lists on the GPU.
    std::uint64_t memoryBytes() const override;

    const GeometrySplittingCounts& counts() const { return m_counts; }
    int depth() const { return m_depth; }
    /// The last frame's triangles, three DEM samples each (reads the GPU; tests).
    std::vector<std::array<glm::ivec2, 3>> readTriangles() const;

private:
    struct Programs {
        gl::Program split, fromLeaves, splitTriangles, arguments, draw;
    };
    struct Capacities {
        std::uint32_t blocks = 1 << 14;
        std::uint32_t leaves = 1 << 14;
        std::uint32_t pending = 1 << 14;
        std::uint32_t triangles = 1 << 16;
    };

    GeometrySplittingStrategy(const io::PyramidManifest& manifest, Programs programs,
                              gl::Query timeQuery, double errorPx, std::size_t maxBytes);
    Status upload(const RoughnessQuadtree& tree, const std::vector<float>& heights);
    /// The lists for m_capacities; an Error, and nothing changed, when they would pass the
    /// memory budget.
    Status allocateLists();
    /// The method's own uniforms (the raster, the grid, τ); the frame is m_frame's block.
    void setMethodUniforms(gl::Program& program) const;
    /// One build of the frame's quadtree and triangles; false when a list overflowed
    /// (m_needed then says how large the lists must grow).
    bool build(const Camera& camera);
    void writeArguments(std::uint32_t countWord, std::uint32_t capacity,
                        std::uint32_t argumentsWord, bool draw);

    std::unique_ptr<PlaneSurface> m_surface;
    PlaneFrame m_frame;  // the camera, the anchor frame and the look of every pass
    Programs m_programs;
    gl::Query m_timeQuery;
    gl::VertexArray m_emptyVertexArray;
    double m_thresholdPx = 1.0;
    std::size_t m_maxBytes = 0;
    int m_depth = 0;
    int m_side = 0;

    gl::Texture m_heights, m_roughness, m_ranges, m_splitFlags;
    gl::Buffer m_counters;
    std::array<gl::Buffer, 2> m_blocks, m_pending;
    gl::Buffer m_leaves, m_triangles;
    Capacities m_capacities;  // of the lists that exist
    Capacities m_needed;      // what the last build asked for
    std::uint64_t m_textureBytes = 0;
    bool m_warnedOverBudget = false;  // said once that a view's lists passed the budget

    GeometrySplittingCounts m_counts;
    LodUpdateStats m_stats;
    double m_lodUpdateUs = 0.0;
    TerrainDrawStats m_lastDraw;
};

}  // namespace terrain::runtime
