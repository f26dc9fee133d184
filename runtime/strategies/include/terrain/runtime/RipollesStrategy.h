// RipollesStrategy: Ripolles, Ramos, Puig-Centelles and Chover, "Real-time tessellation of
// terrain on graphics hardware", as a LodStrategy (LodMethod::Ripolles).
//
// The input mesh is four right triangles about the centre of the raster's square (padded to
// 2^d quads, §4: "an initial mesh composed of 4 triangles"); the height field is on the GPU
// whole (in core, as the paper's Fig. 4 keeps it). Each step refines every leaf triangle by
// the pattern its edges select (Schmiade's seven, §3.1) or coarsens a family back to its
// parent (§3.2), on the GPU as published: a geometry shader over the leaves whose output
// triangles transform feedback captures (ripolles_step.geom), after a compute pass over the
// triangle families (ripolles_families.comp). With coherence (the paper's method,
// and the default) each frame runs one step from the previous frame's tessellation; without
// it each frame starts again from the input mesh and steps until nothing changes — the two
// columns of the paper's Table 3. settle() steps until nothing changes.
//
// The CPU reads back the step's counters (a few words) to size the lists for the next step's
// worst case, to report triangles, and to know when nothing changes.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/gl/Buffer.h"
#include "terrain/gl/Framebuffer.h"
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

/// The last frame's work, read back from the GPU's counters.
struct RipollesCounts {
    std::uint64_t triangles = 0;  ///< leaf triangles drawn
    std::uint64_t families = 0;   ///< refined triangles (families) alive
    std::uint64_t changes = 0;    ///< refinements and coarsenings of the frame's last step
    int steps = 0;                ///< steps the frame ran
};

class RipollesStrategy final : public LodStrategy {
public:
    /// GPU height field and lists together; a raster that needs more for its height field is
    /// refused before it is read, a view whose lists would pass it draws what it has.
    static constexpr std::size_t kDefaultMaxBytes = std::size_t{768} << 20;

    static Result<std::unique_ptr<RipollesStrategy>> open(const std::filesystem::path& pyramid,
                                                          double thresholdPx,
                                                          RipollesParameters parameters = {},
                                                          std::size_t maxBytes = kDefaultMaxBytes);
    /// From a raster in memory (tests): width × height samples, rows running south.
    static Result<std::unique_ptr<RipollesStrategy>> create(
        const io::PyramidManifest& manifest, std::vector<float> heights, double thresholdPx,
        RipollesParameters parameters = {}, std::size_t maxBytes = kDefaultMaxBytes);
    ~RipollesStrategy() override;

    LodMethod method() const override { return LodMethod::Ripolles; }
    const Surface& surface() const override { return *m_surface; }
    /// τ: the longest an edge may look on screen, pixels (the distance criterion of §4).
    void setErrorPx(double errorPx) override { m_thresholdPx = errorPx; }
    double errorPx() const override { return m_thresholdPx; }

    const LodUpdateStats& beginFrame(const Camera& camera) override;
    /// Shaded only (style.debugView is ignored); no skirts.
    TerrainDrawStats draw(const Camera& camera, const TerrainStyle& style) override;
    void endFrame(FrameTelemetry& t) override;
    /// Wall time of the frame's steps, counters read back included.
    double lodUpdateUs() const override { return m_lodUpdateUs; }

    /// Steps until nothing changes: the tessellation the view asks for, as the coherent
    /// method reaches it over frames.
    bool settle(const Camera& camera, std::chrono::milliseconds timeout) override;
    std::uint64_t loadsOutstanding() const override { return 0; }
    const TileFault* fatalFault() const override { return nullptr; }
    void drain(std::chrono::milliseconds) override {}
    std::uint64_t memoryBytes() const override;

    const RipollesCounts& counts() const { return m_counts; }
    /// Back to the input mesh (the next frame starts there).
    void reset();
    /// One step for `camera` (tests); false when nothing changed.
    bool step(const Camera& camera);
    /// The current tessellation's triangles, DEM samples (reads the GPU; tests).
    std::vector<std::array<glm::vec2, 3>> readTriangles() const;

private:
    struct Programs {
        gl::Program families, step, bookkeeping, merge, draw;
    };

    RipollesStrategy(const io::PyramidManifest& manifest, Programs programs, gl::Query timeQuery,
                     gl::Framebuffer stepTarget, double thresholdPx, RipollesParameters parameters,
                     std::size_t maxBytes);
    Status upload(const std::vector<float>& heights);
    /// Lists large enough for one more step from m_counts; false past the budget.
    bool reserve();
    /// The method's own uniforms (the raster, τ); the frame is m_frame's block.
    void setMethodUniforms(gl::Program& program) const;
    void bookkeeping(int phase);
    void readCounters();

    std::unique_ptr<PlaneSurface> m_surface;
    PlaneFrame m_frame;  // the camera, the anchor frame and the look of every pass
    Programs m_programs;
    gl::Query m_timeQuery;
    gl::Framebuffer m_stepTarget;  ///< 1 × 1: the leaves' pass draws, rasterising nothing
    gl::VertexArray m_emptyVertexArray;
    double m_thresholdPx = 1.0;
    RipollesParameters m_parameters;
    std::size_t m_maxBytes = 0;
    int m_squareSamples = 0;  ///< 2^d: the tessellated square's side, in samples

    gl::Texture m_heights;
    gl::Buffer m_counters;
    std::array<gl::Buffer, 2> m_leaves;  ///< [m_current] the tessellation, the other the next
    int m_current = 0;
    gl::Buffer m_families, m_freeSlots, m_freedSlots;
    std::uint64_t m_leafCapacity = 0, m_familyCapacity = 0;
    std::uint64_t m_familySlots = 0;  ///< slots handed out so far (the families' used length)
    bool m_warnedOverBudget = false;

    RipollesCounts m_counts;
    LodUpdateStats m_stats;
    double m_lodUpdateUs = 0.0;
    TerrainDrawStats m_lastDraw;
};

}  // namespace terrain::runtime
