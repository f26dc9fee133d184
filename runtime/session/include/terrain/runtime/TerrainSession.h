// TerrainSession: one open pyramid, planar or globe, being flown through — the tile
// streamer, the LOD quadtree over the pyramid's Surface and the terrain renderer — and the
// frame protocol that ties them together, so every program (terrain-render, the viewer, the
// benchmarks, tests) runs the same frame on either surface:
//
//   beginFrame(camera)  finished reads in; the LOD tree updated for the camera (unless
//                       frozen); the skirt depths of the draw list assigned;
//   draw(camera, style) the one instanced draw into the caller's bound framebuffer (any
//                       number of times: a frozen LOD seen from another camera, say);
//   endFrame(t)         requests no longer wanted cancelled; `t` filled with the
//                       streaming, cache, LOD and draw columns of the telemetry log.
//
// The caller owns the GL context (current on this thread), the framebuffer, the clock
// and the frame/time columns of the telemetry (frame, time_s, frame_ms). The camera follows
// the surface's conventions: the pyramid's map frame on the plane, ECEF with its frame
// east-north-up at its position on the globe (placeOnGlobe).
//
// It is the LodStrategy of the methods that stream patches through the quadtree and draw
// them in the one tessellated draw: Yusov & Shevtsov 2011 (the default), chunked LOD
// (Ulrich 2002: the same quadtree split at the whole τ, chunks drawn at full resolution)
// the uniform grid (every leaf split to the finest level, drawn at full resolution) and
// Valdetaro et al. 2011 (the same finest-level grid, each patch cut into the paper's tiles
// and drawn by ValdetaroRenderer) and Livny et al. 2007 (the quadtree split by Eq. 1,
// drawn by LivnyRenderer) and CDLOD (Strugar 2009: the quadtree by distance ranges, drawn
// morphed by CdlodRenderer). Only Yusov's draws globes (lodMethodSupports).
#pragma once

#include "terrain/base/Result.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/CdlodRenderer.h"
#include "terrain/runtime/FrameTelemetry.h"
#include "terrain/runtime/ImagerySelection.h"
#include "terrain/runtime/LivnyRenderer.h"
#include "terrain/runtime/LodMethod.h"
#include "terrain/runtime/LodQuadtree.h"
#include "terrain/runtime/LodStrategy.h"
#include "terrain/runtime/PatchDraw.h"
#include "terrain/runtime/PatchRenderer.h"
#include "terrain/runtime/Surface.h"
#include "terrain/runtime/TerrainRenderer.h"
#include "terrain/runtime/TileStreamer.h"
#include "terrain/runtime/ValdetaroRenderer.h"

#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <vector>

namespace terrain::runtime {

struct TerrainSessionOptions {
    /// Any method but the RTIN (refused: openLodStrategy opens it).
    LodMethod method = LodMethod::Yusov2011;
    ValdetaroParameters valdetaro;  ///< Valdetaro2011 only
    RipollesParameters ripolles;    ///< Ripolles only (openLodStrategy)
    TileStreamerOptions streaming;
    /// A drawn patch's samples span at most a pixel (LodOptions::maxSamplePx): the picture's
    /// shading is as fine as its pixels.
    LodOptions lod{.maxSamplePx = 1.0};
    TerrainRendererOptions renderer;
};

/// Render thread only; destroy it before its GL context.
class TerrainSession final : public LodStrategy {
public:
    /// Opens the pyramid (errors name it; a method that does not draw its surface is one),
    /// starts streaming, builds the renderer. Where the method draws the pyramid's imagery
    /// it returns once every layer's coarsest tiles are resident (or absent, or failed), so
    /// the first frame wears imagery rather than the plain tint (loadImageryRoots).
    static Result<std::unique_ptr<TerrainSession>> open(const std::filesystem::path& pyramid,
                                                        const TerrainSessionOptions& options);
    ~TerrainSession() override;
    TerrainSession(const TerrainSession&) = delete;
    TerrainSession& operator=(const TerrainSession&) = delete;

    /// Starts a frame: takes finished reads, then (unless the LOD is frozen) updates the
    /// tree for `camera` and rebuilds the draw list. Allocates nothing once warm.
    const LodUpdateStats& beginFrame(const Camera& camera) override;
    /// Draws this frame's patches seen from `camera` into the bound framebuffer, whose
    /// depth must be cleared to 0 (reversed Z). Between beginFrame and endFrame.
    /// Chunked LOD and the uniform grid draw every block at its patch's full resolution,
    /// whatever `style` asks.
    TerrainDrawStats draw(const Camera& camera, const TerrainStyle& style) override;
    /// Ends the frame and fills every column of `t` but frame, time_s and frame_ms (LOD
    /// and draw columns from this frame's beginFrame and its last draw). Its streaming and
    /// cache counts include those of the frames settle() ran since the last endFrame.
    void endFrame(FrameTelemetry& t) override;

    /// Runs frames (without drawing) for `camera` until no split waits for tiles and
    /// nothing is loading, so the next frame shows the settled view; false on timeout, or
    /// at once when fatalFault() says nothing can be drawn. Between endFrame and the next
    /// beginFrame. A frozen LOD is settled as it is. Its frames' requests, uploads and
    /// disk reads are counted in the next endFrame's telemetry.
    bool settle(const Camera& camera, std::chrono::milliseconds timeout) override;

    /// The fault no frame can draw around: a root patch failed to read, so there is no
    /// ancestor to draw in place of its data (the plane's frames would be empty, a globe's
    /// cube face the bare ellipsoid). Programs stop with its message (it names the shard and
    /// the patch); nullptr while there is none. Any other failed patch is drawn by its
    /// ancestor.
    const TileFault* fatalFault() const override;

    LodMethod method() const override { return m_method; }
    /// ε (Yusov), τ (chunked LOD); the uniform grid has no threshold.
    void setErrorPx(double errorPx) override;
    double errorPx() const override { return m_tree->options().errorPx; }
    std::uint64_t loadsOutstanding() const override;
    std::uint64_t imageryWaiting() const override;
    void drain(std::chrono::milliseconds timeout) override;
    /// GPU layers in use and the CPU cache's bytes, as of the last endFrame.
    std::uint64_t memoryBytes() const override { return m_memoryBytes; }

    /// A frozen LOD keeps its draw list (and the tree) as they are: beginFrame streams but
    /// decides nothing, so the cut can be inspected from another camera.
    void setLodFrozen(bool frozen) { m_lodFrozen = frozen; }
    bool lodFrozen() const { return m_lodFrozen; }
    /// The method's own rules (chunked LOD's coarse share, the uniform grid's splits) are
    /// applied over `options`.
    void setLodOptions(const LodOptions& options);
    /// Drops the LOD tree and the layers it pins; the next frame selects from the root
    /// again. The stress test calls it at the end to check that no layer stays pinned.
    void restartLod();
    const LodOptions& lodOptions() const { return m_tree->options(); }

    /// This frame's draw list (every patch resident, skirt depths assigned).
    std::span<const PatchDraw> draws() const { return m_draws; }
    const LodUpdateStats& lodStats() const { return m_lodStats; }
    /// This frame's imagery selection (issue 47), or null when the pyramid has no imagery or
    /// the method draws without it (Valdetaro2011, Livny2007, Cdlod: nothing selected, no
    /// imagery tile asked for).
    const ImagerySelection* imagery() const { return m_imagery.get(); }
    const ImagerySelectionStats& imageryStats() const { return m_imageryStats; }
    double lodUpdateUs() const override { return m_lodUpdateUs; }

    TileStreamer& streamer() { return *m_streamer; }
    const TileStreamer& streamer() const { return *m_streamer; }
    const LodQuadtree& tree() const { return *m_tree; }
    const Surface& surface() const override { return *m_surface; }
    const io::PyramidManifest& manifest() const { return m_streamer->manifest(); }
    /// The draw (recordTessFactors and the like, for tests).
    TerrainRenderer& renderer() { return m_renderer; }

private:
    TerrainSession(std::unique_ptr<TileStreamer> streamer, std::unique_ptr<Surface> surface,
                   TerrainRenderer renderer, std::unique_ptr<PatchRenderer> methodRenderer,
                   LodMethod method, const LodOptions& lod);
    /// A virtual patch interpolates its ancestor's tile between the tile's samples: its
    /// bound takes the tile's largest λ on top of the tile's Err(P), however it is drawn.
    void addTileErrorsToVirtualDraws();
    /// Runs streaming frames (no LOD, no draw) until every imagery layer's coarsest tiles
    /// are resident, known absent or failed, or `timeout` passes (the frames then wear the
    /// tint until they arrive). Their streaming counts go to the first endFrame.
    void loadImageryRoots(std::chrono::milliseconds timeout);

    // Declared in destruction order's reverse: the tree holds pins in the streamer's pool.
    std::unique_ptr<TileStreamer> m_streamer;
    std::unique_ptr<Surface> m_surface;  // the renderer holds a reference
    TerrainRenderer m_renderer;
    // Valdetaro2011, Livny2007 and Cdlod draw with their own; null for the methods that
    // draw with m_renderer.
    std::unique_ptr<PatchRenderer> m_methodRenderer;
    std::unique_ptr<LodQuadtree> m_tree;

    std::vector<PatchDraw> m_draws;
    // The imagery the draws wear (issue 47): selected in beginFrame for its draw list.
    std::unique_ptr<ImagerySelection> m_imagery;
    ImagerySelectionStats m_imageryStats;
    LodUpdateStats m_lodStats;
    double m_lodUpdateUs = 0.0;
    TerrainDrawStats m_lastDraw;
    LodMethod m_method = LodMethod::Yusov2011;
    std::uint64_t m_memoryBytes = 0;
    /// The streaming counts of settle()'s frames, for the next endFrame.
    FrameTelemetry m_unreportedCounts;
    bool m_lodFrozen = false;
};

}  // namespace terrain::runtime
