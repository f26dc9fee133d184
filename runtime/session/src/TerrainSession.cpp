// TerrainSession: the frame protocol of streamer, LOD tree and renderer, on either surface.
#include "terrain/runtime/TerrainSession.h"

#include "terrain/base/Assert.h"
#include "terrain/pyramid/NativeTiles.h"
#include "terrain/pyramid/PyramidReader.h"
#include "terrain/runtime/CdlodRenderer.h"
#include "terrain/runtime/LivnyRenderer.h"
#include "terrain/runtime/PlaneSurface.h"
#include "terrain/runtime/SkirtDepth.h"
#include "terrain/runtime/ValdetaroTiles.h"

#include <cmath>
#include <limits>
#include <utility>

namespace terrain::runtime {
namespace {

using Clock = std::chrono::steady_clock;

/// How long open() waits for the imagery layers' coarsest tiles: a few reads, well within
/// it unless the I/O thread hangs (the frames then start with the tint).
constexpr std::chrono::milliseconds kImageryRootsTimeout{60'000};

/// The quadtree rules of `method` over the caller's options.
LodOptions lodOptionsFor(LodMethod method, LodOptions options) {
    // The uniform grid and Valdetaro's flat grid of tiles: the finest level in view.
    options.splitToFinest = method == LodMethod::Uniform || method == LodMethod::Valdetaro2011;
    if (method == LodMethod::ChunkedLod) {
        // Ulrich 2002, "Rendering massive terrains using chunked level of detail control":
        // a chunk is split while its geometric error δ — here Err(P), the largest vertical
        // distance of its full mesh to the DEM's samples — projects to more than τ,
        // ρ = δ · K / D with D the distance to the chunk's box. K · δ / D is Err_Scr(P) with
        // γ = K, so the quadtree's test is Ulrich's at the whole τ (no share of it left to
        // a fine stage), re-decided without hysteresis.
        options.coarseShare = 1.0;
        options.hysteresis = 1.0;
    }
    if (method == LodMethod::Cdlod) {
        // Strugar 2009: a node is subdivided while the camera is within its children's
        // range; ranges double level by level (LodQuadtree's SplitRule::ProjectedSpacing).
        options.splitRule = SplitRule::ProjectedSpacing;
        options.coarseShare = 1.0;
        options.hysteresis = 1.0;
    }
    if (method == LodMethod::Livny2007) {
        // Livny 2007, §3 "Runtime Rendering": a top-down traversal each frame, a patch split
        // when an edge's ε = ρ · l / d exceeds 1 — the whole threshold, no hysteresis.
        options.splitRule = SplitRule::LivnyEdges;
        options.coarseShare = 1.0;
        options.hysteresis = 1.0;
    }
    return options;
}

/// The comparison methods' own draws; null for those TerrainRenderer draws.
Result<std::unique_ptr<PatchRenderer>> createMethodRenderer(const std::filesystem::path& pyramid,
                                                            const TileStreamer& streamer,
                                                            const TerrainSessionOptions& options) {
    const int instances = streamer.pool().capacity();
    const auto owned = [&](auto drawn) -> Result<std::unique_ptr<PatchRenderer>> {
        if (!drawn) return Error{pyramid.string() + ": " + drawn.error().message};
        using Drawn = std::decay_t<decltype(drawn.value())>;
        return std::unique_ptr<PatchRenderer>(std::make_unique<Drawn>(std::move(drawn).value()));
    };
    switch (options.method) {
        case LodMethod::Valdetaro2011: {
            // The paper's preprocessing (§6.1–6.2), once, from the finest level.
            auto reader = io::PyramidReader::open(pyramid);
            if (!reader) return reader.error();
            auto tiles = analyseValdetaroTiles(reader.value());
            if (!tiles) return tiles.error();
            return owned(ValdetaroRenderer::create(streamer.layout(), instances, tiles.value(),
                                                   options.valdetaro));
        }
        case LodMethod::Livny2007:
            return owned(LivnyRenderer::create(streamer.layout(), instances));
        case LodMethod::Cdlod:
            return owned(CdlodRenderer::create(streamer.layout(), instances));
        case LodMethod::Yusov2011:
        case LodMethod::ChunkedLod:
        case LodMethod::Uniform:
        case LodMethod::Lee2011:
        case LodMethod::Ripolles:
        case LodMethod::Rtin:
            break;
    }
    return std::unique_ptr<PatchRenderer>();
}

/// Chunked LOD and the uniform grid draw each patch as its full mesh.
bool drawsFullPatches(LodMethod method) {
    return method == LodMethod::ChunkedLod || method == LodMethod::Uniform;
}

}  // namespace

Result<std::unique_ptr<TerrainSession>> TerrainSession::open(const std::filesystem::path& pyramid,
                                                             const TerrainSessionOptions& options) {
    if (lodMethodInfo(options.method).inCore)
        return Error{std::string(lodMethodName(options.method)) +
                     ": not a streaming quadtree method (openLodStrategy opens it)"};
    auto streamer = TileStreamer::open(pyramid, options.streaming);
    if (!streamer) return streamer.error();
    std::unique_ptr<Surface> surface =
        makeSurface(streamer.value()->manifest(), streamer.value()->nativeGrids());
    if (Status supported = lodMethodSupports(options.method, surface->kind()); !supported)
        return Error{pyramid.string() + ": a " + std::string(surfaceName(surface->kind())) +
                     " pyramid: " + supported.error().message};
    // The tree draws only resident patches, so the pool's capacity bounds one draw; bare
    // patches take no layer, so where the surface has them (the globe) the draw list can
    // outgrow it: a bound of their own.
    const int maxInstances =
        streamer.value()->pool().capacity() + (surface->drawsBareSurface() ? 4096 : 0);
    auto renderer = TerrainRenderer::create(*surface, maxInstances, options.renderer);
    if (!renderer) return Error{pyramid.string() + ": " + renderer.error().message};
    auto methodRenderer = createMethodRenderer(pyramid, *streamer.value(), options);
    if (!methodRenderer) return methodRenderer.error();
    std::unique_ptr<TerrainSession> session(new TerrainSession(
        std::move(streamer).value(), std::move(surface), std::move(renderer).value(),
        std::move(methodRenderer).value(), options.method, options.lod));
    session->loadImageryRoots(kImageryRootsTimeout);
    return session;
}

TerrainSession::TerrainSession(std::unique_ptr<TileStreamer> streamer,
                               std::unique_ptr<Surface> surface, TerrainRenderer renderer,
                               std::unique_ptr<PatchRenderer> methodRenderer, LodMethod method,
                               const LodOptions& lod)
    : m_streamer(std::move(streamer)),
      m_surface(std::move(surface)),
      m_renderer(std::move(renderer)),
      m_methodRenderer(std::move(methodRenderer)),
      m_tree(std::make_unique<LodQuadtree>(*m_streamer, *m_surface, lodOptionsFor(method, lod))),
      m_method(method) {
    m_draws.reserve(static_cast<std::size_t>(m_streamer->pool().capacity()));
    // The methods with their own renderers draw without imagery: nothing to select or ask for.
    if (!m_streamer->manifest().imagery.empty() && !m_methodRenderer)
        m_imagery = std::make_unique<ImagerySelection>(*m_surface, m_streamer->manifest());
}

void TerrainSession::loadImageryRoots(std::chrono::milliseconds timeout) {
    if (!m_imagery) return;
    struct Tile {
        int layer = 0;
        io::PatchId id;
    };
    std::vector<Tile> roots;
    for (int layer = 0; layer < m_imagery->layerCount(); ++layer)
        for (const io::PatchId& id : m_imagery->coarsestTiles(layer)) roots.push_back({layer, id});
    ImageryStreamer& imagery = m_streamer->imagery();
    // A GPU budget too small for them all would wait for layers no frame frees.
    if (static_cast<int>(roots.size()) > imagery.pool().capacity()) return;
    const auto deadline = Clock::now() + timeout;
    while (true) {
        m_streamer->beginFrame();
        bool loaded = true;
        for (const Tile& root : roots) {
            // Asked for first, as the height roots are (LodQuadtree): nothing draws without them.
            imagery.want(root.layer, root.id, std::numeric_limits<float>::max());
            const io::ImageryTileInfo* info = imagery.tileInfo(root.layer, root.id);
            const bool absent = info != nullptr && !info->present;
            if (!imagery.gpuLayer(root.layer, root.id) && !absent &&
                !imagery.hasFailed(root.layer, root.id))
                loaded = false;
        }
        FrameTelemetry frame;
        m_streamer->endFrame(frame);
        addStreamingCounts(m_unreportedCounts, frame);
        if (loaded) return;
        const auto now = Clock::now();
        if (now > deadline) return;
        m_streamer->waitForReads(std::chrono::ceil<std::chrono::milliseconds>(deadline - now));
    }
}

TerrainSession::~TerrainSession() {
    m_tree.reset();  // unpins its patches while the pool exists
}

void TerrainSession::setLodOptions(const LodOptions& options) {
    m_tree->setOptions(lodOptionsFor(m_method, options));
}

void TerrainSession::setErrorPx(double errorPx) {
    LodOptions options = m_tree->options();
    options.errorPx = errorPx;
    m_tree->setOptions(options);
}

std::uint64_t TerrainSession::loadsOutstanding() const { return m_streamer->loadsOutstanding(); }

std::uint64_t TerrainSession::imageryWaiting() const {
    return m_imageryStats.waiting + m_streamer->imagery().loadsOutstanding();
}

void TerrainSession::drain(std::chrono::milliseconds timeout) { m_streamer->drain(timeout); }

void TerrainSession::restartLod() {
    const LodOptions options = m_tree->options();
    m_tree.reset();  // unpins before the new tree exists
    m_tree = std::make_unique<LodQuadtree>(*m_streamer, *m_surface, options);
    m_draws.clear();
}

const LodUpdateStats& TerrainSession::beginFrame(const Camera& camera) {
    m_streamer->beginFrame();
    m_lastDraw = {};
    if (m_lodFrozen) {
        m_lodUpdateUs = 0.0;
        m_lodStats.splits = m_lodStats.merges = m_lodStats.evaluations = 0;
        return m_lodStats;
    }
    const auto start = Clock::now();
    m_lodStats = m_tree->update(camera, m_draws);
    addTileErrorsToVirtualDraws();
    assignSkirtDepths(m_draws, m_streamer->pool());
    if (m_imagery)
        m_imageryStats = m_imagery->select(camera, m_draws, m_streamer->imagery(), *m_streamer);
    m_lodUpdateUs = std::chrono::duration<double, std::micro>(Clock::now() - start).count();
    return m_lodStats;
}

void TerrainSession::addTileErrorsToVirtualDraws() {
    for (PatchDraw& draw : m_draws) {
        if (!draw.isVirtual) continue;
        const float lambda = m_streamer->pool().maxBlockErrorM(draw.tileId).value_or(0.0f);
        if (io::isNativeTile(draw.id)) {
            // A native window of depth k (runtime/lod NativeWindowTree) draws the tile's
            // samples on their own triangles: drawn whole, or simplified by 2^d ≤ 2^k, each of
            // its triangles lies within one source cell, where only its geometric terms count.
            // Simplified further, its triangles span 2^(d−k) of the tile's cells: the tile's
            // λ(d − k), at most its largest.
            const int depth = -std::ilogb(draw.texelStep);
            for (int d = 1; d <= 4; ++d)
                if (d > depth) draw.bareBlockErrorsM[static_cast<std::size_t>(d - 1)] += lambda;
            continue;
        }
        draw.errorM += lambda;
        for (float& d : draw.bareBlockErrorsM) d += lambda;
    }
}

TerrainDrawStats TerrainSession::draw(const Camera& camera, const TerrainStyle& style) {
    if (m_methodRenderer) {
        m_lastDraw = m_methodRenderer->draw(camera, planeGeometry(*m_surface), m_streamer->pool(),
                                            m_draws, style, errorPx());
        return m_lastDraw;
    }
    // The imagery of this frame's draw list (the comparison methods above draw without).
    std::optional<DrapedImagery> draped;
    if (m_imagery)
        draped.emplace(DrapedImagery{*m_imagery, m_streamer->imageryTiles(),
                                     m_streamer->imagery().pool().maxAnisotropy()});
    const DrapedImagery* imagery = draped ? &*draped : nullptr;
    if (drawsFullPatches(m_method)) {
        TerrainStyle full = style;
        full.fixedTessFactor = m_surface->layout().blockQuads();
        m_lastDraw = m_renderer.draw(camera, m_streamer->pool(), m_draws, full, errorPx(), imagery);
        return m_lastDraw;
    }
    m_lastDraw = m_renderer.draw(camera, m_streamer->pool(), m_draws, style, errorPx(), imagery);
    return m_lastDraw;
}

void TerrainSession::endFrame(FrameTelemetry& t) {
    m_streamer->endFrame(t);
    addStreamingCounts(t, m_unreportedCounts);
    m_unreportedCounts = {};
    t.patchesDrawn = m_lodStats.drawn;
    t.patchesCulled = m_lodStats.culled + m_lodStats.horizonCulled;
    t.patchesHorizonCulled = m_lodStats.horizonCulled;
    t.lodUpdateUs = m_lodUpdateUs;
    t.lodSplits = m_lodStats.splits;
    t.lodMerges = m_lodStats.merges;
    t.lodWaitingSplits = m_lodStats.waitingSplits;
    t.drawCalls = static_cast<std::uint64_t>(m_lastDraw.drawCalls);
    t.triangles = m_lastDraw.triangles;
    t.gpuMs = m_lastDraw.drawCalls > 0 && m_lastDraw.gpuMs > 0.0 ? m_lastDraw.gpuMs
                                                                 : FrameTelemetry::kNoValue;
    m_memoryBytes =
        t.gpuLayersUsed * cache::GpuTilePool::bytesPerLayer(m_surface->layout()) + t.cpuCacheBytes;
}

const TileFault* TerrainSession::fatalFault() const {
    for (const io::PatchId& root : m_surface->roots())
        if (const TileFault* fault = m_streamer->faultOf(root)) return fault;
    return nullptr;
}

bool TerrainSession::settle(const Camera& camera, std::chrono::milliseconds timeout) {
    if (m_lodFrozen) return true;  // nothing would change: the cut is held as it is
    const auto deadline = Clock::now() + timeout;
    while (true) {
        const LodUpdateStats& lod = beginFrame(camera);
        if (fatalFault() != nullptr) return false;  // it would wait for nothing
        // The imagery too: every listed tile resident (or failed), none on its way.
        const bool settled = !m_draws.empty() && lod.waitingSplits == 0 && lod.splits == 0 &&
                             lod.merges == 0 && m_streamer->loadsOutstanding() == 0 &&
                             imageryWaiting() == 0;
        // Its streaming is reported with the next frame the caller ends: without it a
        // settled flight's telemetry would show none of the loads that settled it.
        FrameTelemetry frame;
        m_streamer->endFrame(frame);
        addStreamingCounts(m_unreportedCounts, frame);
        if (settled) return true;
        const auto now = Clock::now();
        if (now > deadline) return false;
        // Nothing changes until a read finishes; when none is left, the next frame uploads
        // what waits in the CPU cache.
        m_streamer->waitForReads(std::chrono::ceil<std::chrono::milliseconds>(deadline - now));
    }
}

}  // namespace terrain::runtime
