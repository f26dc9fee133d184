// LodStrategy: what chooses and draws a frame's geometry, behind one interface, so the
// programs (terrain-bench, terrain-render, the tests) fly, draw and measure every LOD method
// the same way (DESIGN.md, "LOD strategies and comparison methods"). The frame protocol is
// TerrainSession's:
//
//   beginFrame(camera)   the method decides the frame's geometry for `camera`;
//   draw(camera, style)  draws it into the bound framebuffer (depth cleared to 0, reversed
//                        Z), any number of times;
//   endFrame(t)          fills the streaming, cache, LOD and draw columns of `t`.
//
// The pyramid, the camera, the telemetry and the accuracy harness (AccuracyProbe) are
// shared; each method keeps its own selection and drawing. Render thread only.
#pragma once

#include "terrain/runtime/Camera.h"
#include "terrain/runtime/FrameTelemetry.h"
#include "terrain/runtime/LodMethod.h"
#include "terrain/runtime/LodQuadtree.h"
#include "terrain/runtime/Surface.h"
#include "terrain/runtime/TerrainRenderer.h"

#include <chrono>
#include <cstdint>

namespace terrain::runtime {

struct TileFault;

class LodStrategy {
public:
    virtual ~LodStrategy() = default;

    virtual LodMethod method() const = 0;
    /// The pyramid's surface: where its patches lie, and the camera's conventions there.
    virtual const Surface& surface() const = 0;

    /// The method's own threshold, pixels: ε for Yusov, τ for chunked LOD and the RTIN.
    /// Methods without one (the uniform grid) ignore it. The strategy holds it: its selection
    /// and its draw both take it from here, and nothing else sets it.
    virtual void setErrorPx(double errorPx) = 0;
    virtual double errorPx() const = 0;

    virtual const LodUpdateStats& beginFrame(const Camera& camera) = 0;
    virtual TerrainDrawStats draw(const Camera& camera, const TerrainStyle& style) = 0;
    virtual void endFrame(FrameTelemetry& t) = 0;
    /// Microseconds the last beginFrame spent deciding the geometry.
    virtual double lodUpdateUs() const = 0;

    /// Runs frames without drawing until the view's data is in (TerrainSession::settle);
    /// between endFrame and the next beginFrame. Methods that stream nothing return true.
    virtual bool settle(const Camera& camera, std::chrono::milliseconds timeout) = 0;
    /// Reads requested and not yet finished (0 for methods that stream nothing).
    virtual std::uint64_t loadsOutstanding() const = 0;
    /// Imagery tiles this frame's draw wants and does not have (drawn from an ancestor
    /// meanwhile), plus imagery reads in flight: 0 once the imagery is at full detail (0 for
    /// methods that drape none).
    virtual std::uint64_t imageryWaiting() const { return 0; }
    /// The fault no frame can draw around (TerrainSession::fatalFault), or nullptr.
    virtual const TileFault* fatalFault() const = 0;
    /// Waits up to `timeout` for reads in flight, before the strategy is destroyed.
    virtual void drain(std::chrono::milliseconds timeout) = 0;

    /// Bytes the method holds to draw: GPU tile layers in use and the CPU tile cache for the
    /// streaming methods; meshes, buffers and CPU arrays for the others. After endFrame.
    virtual std::uint64_t memoryBytes() const = 0;
};

/// endFrame of a method that streams nothing: the LOD time and the last draw's calls,
/// triangles and GPU time (none when it was not measured).
inline void writeDrawTelemetry(FrameTelemetry& t, double lodUpdateUs,
                               const TerrainDrawStats& draw) {
    t.lodUpdateUs = lodUpdateUs;
    t.drawCalls = static_cast<std::uint64_t>(draw.drawCalls);
    t.triangles = draw.triangles;
    t.gpuMs = draw.drawCalls > 0 && draw.gpuMs > 0.0 ? draw.gpuMs : FrameTelemetry::kNoValue;
}

}  // namespace terrain::runtime
