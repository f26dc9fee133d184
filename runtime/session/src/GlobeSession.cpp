#include "terrain/runtime/GlobeSession.h"

#include "terrain/globe/CubeSphere.h"
#include "terrain/pyramid/GlobeLayout.h"
#include "terrain/runtime/SkirtDepth.h"

#include <optional>
#include <utility>

namespace terrain::runtime {
namespace {
using Clock = std::chrono::steady_clock;
}

Result<std::unique_ptr<GlobeSession>> GlobeSession::open(const std::filesystem::path& pyramid,
                                                         const GlobeSessionOptions& options) {
    auto streamer = TileStreamer::open(pyramid, options.streaming);
    if (!streamer) return streamer.error();
    if (!streamer.value()->manifest().globe)
        return Error{pyramid.string() +
                     ": a planar pyramid, not a globe (build with terrain-build --globe)"};
    // Bare patches take no layer, so the draw list can outgrow the pool: a bound of its own.
    const int maxInstances = streamer.value()->pool().capacity() + 4096;
    auto renderer = GlobeRenderer::create(streamer.value()->manifest(), maxInstances);
    if (!renderer) return Error{pyramid.string() + ": " + renderer.error().message};
    return std::unique_ptr<GlobeSession>(
        new GlobeSession(std::move(streamer).value(), std::move(renderer).value(), options.lod));
}

GlobeSession::GlobeSession(std::unique_ptr<TileStreamer> streamer, GlobeRenderer renderer,
                           const GlobeLodOptions& lod)
    : m_streamer(std::move(streamer)),
      m_renderer(std::move(renderer)),
      m_lod(m_streamer->manifest(), *m_streamer, lod) {}

const GlobeLodStats& GlobeSession::beginFrame(const Camera& camera) {
    m_streamer->beginFrame();
    m_lastDraw = {};
    const auto start = Clock::now();
    m_lodStats = m_lod.select(camera, m_draws);
    // A virtual patch interpolates its ancestor's tile between the tile's samples: its bound
    // takes the tile's largest λ on top of the tile's Err(P), however it is tessellated.
    for (GlobePatchDraw& draw : m_draws) {
        if (!draw.isVirtual) continue;
        const std::optional<float> tileLambda =
            m_streamer->pool().maxBlockErrorM(io::layoutPatchOf(draw.tileId));
        const float lambda = tileLambda.value_or(0.0f);
        draw.errorM += lambda;
        for (float& d : draw.bareBlockErrorsM) d += lambda;
    }
    assignSkirtDepths(m_draws, m_streamer->pool());
    m_lodUpdateUs = std::chrono::duration<double, std::micro>(Clock::now() - start).count();
    return m_lodStats;
}

TerrainDrawStats GlobeSession::draw(const Camera& camera, const TerrainStyle& style) {
    m_lastDraw = m_renderer.draw(camera, m_streamer->pool(), m_draws, style);
    return m_lastDraw;
}

void GlobeSession::endFrame(FrameTelemetry& t) {
    m_streamer->endFrame(t);
    t.patchesDrawn = m_lodStats.drawn;
    t.patchesCulled = m_lodStats.frustumCulled + m_lodStats.horizonCulled;
    t.patchesHorizonCulled = m_lodStats.horizonCulled;
    t.lodUpdateUs = m_lodUpdateUs;
    t.drawCalls = static_cast<std::uint64_t>(m_lastDraw.drawCalls);
    t.triangles = m_lastDraw.triangles;
    t.gpuMs = m_lastDraw.drawCalls > 0 && m_lastDraw.gpuMs > 0.0 ? m_lastDraw.gpuMs
                                                                 : FrameTelemetry::kNoValue;
}

const TileFault* GlobeSession::fatalFault() const {
    for (int face = 0; face < globe::kCubeFaces; ++face)
        if (const TileFault* fault =
                m_streamer->faultOf(io::layoutPatchOf(globe::GlobePatchId{face, 0, 0, 0})))
            return fault;
    return nullptr;
}

bool GlobeSession::settle(const Camera& camera, std::chrono::milliseconds timeout) {
    const auto deadline = Clock::now() + timeout;
    while (true) {
        const GlobeLodStats& lod = beginFrame(camera);
        if (fatalFault() != nullptr) return false;  // it would draw a wrong picture
        const bool settled = lod.waitingSplits == 0 && m_streamer->loadsOutstanding() == 0;
        FrameTelemetry ignored;
        m_streamer->endFrame(ignored);
        if (settled) return true;
        const auto now = Clock::now();
        if (now > deadline) return false;
        m_streamer->waitForReads(std::chrono::ceil<std::chrono::milliseconds>(deadline - now));
    }
}

}  // namespace terrain::runtime
