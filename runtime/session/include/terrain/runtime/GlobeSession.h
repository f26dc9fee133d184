// GlobeSession: TerrainSession's frame protocol for a globe pyramid (DESIGN.md, "The globe"):
// the tile streamer, the globe LOD (GlobeLod) and the globe renderer (GlobeRenderer).
//
//   beginFrame(camera)  finished reads in; the patches for the camera selected from the six
//                       cube faces; the skirt depths assigned;
//   draw(camera, style) the one instanced draw into the caller's bound framebuffer;
//   endFrame(t)         requests no longer wanted cancelled; `t` filled with the streaming,
//                       cache, LOD and draw columns (culled = frustum + horizon).
//
// The camera is ECEF with its frame east-north-up at its position (placeOnGlobe).
#pragma once

#include "terrain/base/Result.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/FrameTelemetry.h"
#include "terrain/runtime/GlobeLod.h"
#include "terrain/runtime/GlobeRenderer.h"
#include "terrain/runtime/TileStreamer.h"

#include <chrono>
#include <filesystem>
#include <memory>
#include <span>
#include <vector>

namespace terrain::runtime {

struct GlobeSessionOptions {
    TileStreamerOptions streaming;
    GlobeLodOptions lod;
};

/// Render thread only; destroy it before its GL context.
class GlobeSession {
public:
    /// Opens a globe pyramid (a planar one is an Error that says so), starts streaming,
    /// builds the renderer.
    static Result<std::unique_ptr<GlobeSession>> open(const std::filesystem::path& pyramid,
                                                      const GlobeSessionOptions& options);

    const GlobeLodStats& beginFrame(const Camera& camera);
    TerrainDrawStats draw(const Camera& camera, const TerrainStyle& style);
    void endFrame(FrameTelemetry& t);
    /// Runs frames (without drawing) until no split waits for tiles and nothing is loading;
    /// false on timeout, or at once when fatalFault() is set.
    bool settle(const Camera& camera, std::chrono::milliseconds timeout);

    /// The fault no frame can draw around: a cube face's root patch failed to read, so that
    /// face has no ancestor to draw its data and would show the bare ellipsoid in its place.
    /// Programs stop with its message (it names the shard and the patch); nullptr while
    /// there is none. Any other failed patch is drawn by its ancestor.
    const TileFault* fatalFault() const;

    std::span<const GlobePatchDraw> draws() const { return m_draws; }
    const GlobeLodStats& lodStats() const { return m_lodStats; }
    double lodUpdateUs() const { return m_lodUpdateUs; }
    GlobeLod& lod() { return m_lod; }
    TileStreamer& streamer() { return *m_streamer; }
    const io::PyramidManifest& manifest() const { return m_streamer->manifest(); }

private:
    GlobeSession(std::unique_ptr<TileStreamer> streamer, GlobeRenderer renderer,
                 const GlobeLodOptions& lod);

    std::unique_ptr<TileStreamer> m_streamer;
    GlobeRenderer m_renderer;
    GlobeLod m_lod;
    std::vector<GlobePatchDraw> m_draws;
    GlobeLodStats m_lodStats;
    double m_lodUpdateUs = 0.0;
    TerrainDrawStats m_lastDraw;
};

}  // namespace terrain::runtime
