// TileStreamer: completions into the CPU cache, uploads from it within the frame budget,
// and a map of the loads the LOD wants, swept every frame for cancellations.
#include "terrain/runtime/TileStreamer.h"

#include "terrain/base/Assert.h"

#include <fmt/format.h>

#include <algorithm>
#include <iterator>
#include <utility>

namespace terrain::runtime {

Result<std::unique_ptr<TileStreamer>> TileStreamer::open(const std::filesystem::path& pyramid,
                                                         const TileStreamerOptions& options) {
    auto manifest = io::readManifest(pyramid);
    if (!manifest) return manifest.error();
    auto nativeGrids = io::readNativeGridManifests(pyramid, manifest.value());
    if (!nativeGrids) return nativeGrids.error();
    if (options.gpuLayers < 1) {
        return Error{fmt::format("{}: the GPU tile pool needs at least 1 layer, not {}",
                                 pyramid.string(), options.gpuLayers)};
    }
    const io::PyramidLayout& layout = manifest.value().layout;
    // A tile the CPU cache cannot hold never reaches the GPU: the terrain would never draw.
    const std::size_t tileBytes =
        cache::TileCache::tileBytes(layout, manifest.value().noData.present);
    if (options.cpuCacheBytes < tileBytes) {
        return Error{
            fmt::format("{}: a CPU tile cache of {} bytes holds no tile; a tile of this "
                        "pyramid needs {} bytes",
                        pyramid.string(), options.cpuCacheBytes, tileBytes)};
    }
    const std::size_t layerBytes = cache::GpuTilePool::bytesPerLayer(layout);
    auto pool = cache::GpuTilePool::create(
        layout, {.budgetBytes = layerBytes * static_cast<std::size_t>(options.gpuLayers),
                 .uploadBudgetBytesPerFrame = options.uploadBytesPerFrame,
                 .ringBytes = 0});
    if (!pool) return Error{pyramid.string() + ": " + pool.error().message};
    auto io = io::IoThread::start(pyramid, ioOptionsFor(options, pool.value()));
    if (!io) return io.error();
    auto imagery = ImageryStreamer::create(*io.value(), options.imagery);
    if (!imagery) return Error{pyramid.string() + ": " + imagery.error().message};
    auto streamer = std::unique_ptr<TileStreamer>(
        new TileStreamer(std::move(manifest).value(), std::move(io).value(),
                         std::move(imagery).value(), std::move(pool).value(), options));
    streamer->m_nativeGrids = std::move(nativeGrids).value();
    return streamer;
}

TileStreamer::TileStreamer(io::PyramidManifest manifest, std::unique_ptr<io::IoThread> io,
                           std::unique_ptr<ImageryStreamer> imagery, cache::GpuTilePool pool,
                           const TileStreamerOptions& options)
    : m_manifest(std::move(manifest)),
      m_io(std::move(io)),
      m_imagery(std::move(imagery)),
      m_cache(options.cpuCacheBytes),
      m_pool(std::move(pool)),
      m_uploadMsPerFrame(options.uploadMsPerFrame),
      m_prefetch(options.prefetch) {
    // Sized for the busiest frames up front; the map and vectors keep their high-water
    // storage, so steady frames do not allocate.
    const auto capacity = static_cast<std::size_t>(m_pool.capacity());
    m_loads.reserve(4 * capacity);
    m_completions.reserve(ioOptionsFor(options, m_pool).maxUnpolled + 64);
}

io::IoThreadOptions TileStreamer::ioOptionsFor(const TileStreamerOptions& options,
                                               const cache::GpuTilePool& pool) {
    // A frame uploads what finished since the last one. The I/O side stops when maxUnpolled
    // results wait for poll(); at its default of 8 tiles a slow frame (one taking longer
    // than 8 reads) made at most 8 tiles resident, whatever the disk and the upload budget
    // allowed (issue 49). Room for a frame's upload budget of tiles instead: the budget per
    // frame is in bytes, and what waits is bounded by it (plus one tile per reader thread).
    io::IoThreadOptions io = options.io;
    const std::size_t tileBytes = std::max<std::size_t>(1, pool.uploadBytesPerTile());
    const std::size_t tilesPerFrame = (options.uploadBytesPerFrame + tileBytes - 1) / tileBytes;
    io.maxUnpolled = std::max(io.maxUnpolled, tilesPerFrame);
    return io;
}

TileStreamer::~TileStreamer() = default;

void TileStreamer::beginFrame() {
    ++m_frame;
    m_frameCounts = {};
    m_uploadMsThisFrame = 0.0;
    m_cache.resetCounters();
    m_pool.beginFrame();
    m_imagery->beginFrame();
    takeCompletions();
}

void TileStreamer::takeCompletions() {
    m_completions.clear();
    m_io->poll(m_completions);
    for (io::Completion& c : m_completions) {
        if (c.key().isImagery()) {
            m_imagery->takeCompletion(c);
            continue;
        }
        const auto load = m_loads.find(c.id);
        if (load != m_loads.end()) --load->second.liveRequests;
        switch (c.status) {
            case io::CompletionStatus::Completed:
                if (!c.record.info.present) {
                    takeAbsent(c, load);
                    break;
                }
                ++m_ledger.completed;
                ++m_frameCounts.requestsCompleted;
                if (m_cache.insert(std::move(c.record)) == cache::TileCacheInsertResult::TooLarge) {
                    m_io->recycle(std::move(c.record));
                }
                break;
            case io::CompletionStatus::Failed:
                ++m_ledger.failed;
                ++m_frameCounts.requestsFailed;
                // Reported once: a failed patch is never requested again.
                if (m_failed.insert(c.id).second) m_faults.push_back({c.id, std::move(c.error)});
                if (load != m_loads.end() && load->second.liveRequests == 0) m_loads.erase(load);
                break;
            case io::CompletionStatus::Cancelled:
                ++m_ledger.cancelled;
                ++m_frameCounts.requestsCancelled;
                m_io->recycle(std::move(c.record));
                break;
        }
    }
    // Records the cache dropped give their storage back to the reader.
    while (auto evicted = m_cache.takeEvicted()) m_io->recycle(std::move(*evicted));
}

// A patch the pyramid does not store. Read ahead (the sparse globe's grandchildren, whose
// presence only their parent knows), it is remembered and never read again; wanted by the
// LOD (which asks only for the patches their parent lists), the pyramid contradicts itself:
// a fault, counted as a failed read.
void TileStreamer::takeAbsent(io::Completion& c, LoadMap::iterator load) {
    const bool wanted = load != m_loads.end() && !load->second.aheadOnly;
    if (wanted) {
        ++m_ledger.failed;
        ++m_frameCounts.requestsFailed;
        if (m_failed.insert(c.id).second) m_faults.push_back({c.id, std::move(c.error)});
    } else {
        ++m_ledger.completed;
        ++m_frameCounts.requestsCompleted;
        // Bounded: a forgotten absent patch is only read again, should it be asked for.
        if (m_absent.size() >= kMaxKnownAbsent) m_absent.clear();
        m_absent.insert(c.id);
    }
    if (load != m_loads.end() && load->second.liveRequests == 0) m_loads.erase(load);
    m_io->recycle(std::move(c.record));
}

TileStreamer::LoadState& TileStreamer::loadStateOf(const io::PatchId& id, bool* inserted) {
    return m_loads.findOrInsert(id, [&] {
        if (inserted != nullptr) *inserted = true;
        return LoadState{.firstWanted = Clock::now(),
                         .firstWantedFrame = m_frame,
                         .lastWantedFrame = m_frame,
                         .liveRequests = 0,
                         .cancelRequested = false};
    });
}

bool TileStreamer::uploadFromCache(const io::PatchId& id) {
    // The first upload of a frame always goes (each successful one counts a resident load),
    // so a frame slower than the budget still makes progress.
    const bool outOfTime = m_uploadMsPerFrame > 0.0 && m_frameCounts.loadsResident > 0 &&
                           m_uploadMsThisFrame >= m_uploadMsPerFrame;
    if (!m_pool.uploadBudgetLeft() || outOfTime) {
        ++m_frameCounts.gpuUploadsDeferred;
        return false;
    }
    if (!m_pool.allocateEvicting(id)) return false;  // every layer is drawn this frame
    // Looked up only now, so a CPU cache hit is a tile that goes to the GPU.
    const io::PatchRecord* record = m_cache.find(id);
    TERRAIN_ASSERT(record != nullptr, "TileStreamer: upload of a patch not in the CPU cache");
    const Clock::time_point uploadStart = Clock::now();
    const bool uploaded = m_pool.upload(*record);
    m_uploadMsThisFrame +=
        std::chrono::duration<double, std::milli>(Clock::now() - uploadStart).count();
    if (!uploaded) {
        m_pool.release(id);  // the ring is full of this frame's uploads: next frame
        return false;
    }
    return true;
}

const io::PatchInfo* TileStreamer::acquire(const io::PatchId& id, float priority) {
    if (const io::PatchInfo* info = m_pool.info(id)) {
        m_pool.touch(id);
        return info;
    }
    if (m_failed.contains(id)) return nullptr;
    // Read ahead and found absent, yet wanted as stored: read again, and the read's words
    // (naming the shard file) become its fault (takeAbsent).
    m_absent.erase(id);
    LoadState& load = loadStateOf(id);
    load.lastWantedFrame = m_frame;
    if (load.aheadOnly) {
        // Read ahead, wanted now: its latency is what the LOD waits from here.
        load.aheadOnly = false;
        load.firstWanted = Clock::now();
        load.firstWantedFrame = m_frame;
    }
    if (m_cache.contains(id)) {
        if (!uploadFromCache(id)) return nullptr;
        const double ms =
            std::chrono::duration<double, std::milli>(Clock::now() - load.firstWanted).count();
        m_recentLoads.add(ms);
        m_loadLatencies.add(ms);
        ++m_frameCounts.loadsResident;
        if (m_loadObserver) m_loadObserver({id, ms, m_frame - load.firstWantedFrame});
        if (load.liveRequests == 0) m_loads.erase(m_loads.find(id));
        return m_pool.info(id);
    }
    request(id, load, priority);
    return nullptr;
}

void TileStreamer::request(const io::PatchId& id, LoadState& load, float priority) {
    // A live request is only re-prioritised: it may have finished already, its completion
    // waiting for the next poll, and a second request would read the tile twice.
    if (load.liveRequests > 0 && !load.cancelRequested) {
        m_io->reprioritise(id, priority);
        return;
    }
    // A new request (after a cancel, the cancelled one still ends once, as Cancelled or
    // as it finished).
    if (m_io->submit(id, priority)) {
        ++load.liveRequests;
        ++m_ledger.submitted;
        ++m_frameCounts.requestsMade;
        ++m_frameCounts.cpuCacheMisses;
    }
    load.cancelRequested = false;
}

void TileStreamer::prefetch(const io::PatchId& id, float priority) {
    if (!m_prefetch || m_pool.info(id) != nullptr || m_failed.contains(id) ||
        m_absent.contains(id) || m_cache.contains(id))
        return;
    bool fresh = false;
    LoadState& load = loadStateOf(id, &fresh);
    // Asked for already this frame (by acquire, at its own priority): left as it is.
    if (!fresh && load.lastWantedFrame == m_frame) return;
    if (fresh) load.aheadOnly = true;
    load.lastWantedFrame = m_frame;  // wanted this frame: endFrame leaves its request be
    request(id, load, priority);
}

int TileStreamer::layerOf(const io::PatchId& id) const {
    const std::optional<int> layer = m_pool.layerOf(id);
    TERRAIN_ASSERT(layer.has_value(), "TileStreamer::layerOf a patch without a layer");
    return *layer;
}

void TileStreamer::endFrame(FrameTelemetry& t) {
    for (auto it = m_loads.begin(); it != m_loads.end();) {
        const auto next = std::next(it);
        LoadState& load = it->second;
        if (load.lastWantedFrame != m_frame) {
            if (load.liveRequests == 0) {
                m_loads.erase(it);
            } else if (!load.cancelRequested) {
                m_io->cancel(it->first);  // false when it finished already: polled next frame
                load.cancelRequested = true;
            }
        }
        it = next;
    }
    m_pool.endFrame();
    m_imagery->endFrame(t);

    const io::IoThreadStats io = m_io->stats();
    const cache::TileCacheCounters& cpu = m_cache.counters();
    const cache::GpuTilePoolFrameStats& gpu = m_pool.frameStats();
    t.requestsMade = m_frameCounts.requestsMade;
    t.requestsCancelled = m_frameCounts.requestsCancelled;
    t.requestsCompleted = m_frameCounts.requestsCompleted;
    t.requestsFailed = m_frameCounts.requestsFailed;
    t.queueDepth = io.queueDepth;
    t.ioInFlight = io.inFlight;
    t.cpuCacheHits = cpu.hits;
    t.cpuCacheMisses = m_frameCounts.cpuCacheMisses;
    t.cpuCacheEvictions = cpu.evictions;
    t.cpuCacheEntries = m_cache.entryCount();
    t.cpuCacheBytes = m_cache.bytes();
    t.cpuCacheBudgetBytes = m_cache.budgetBytes();
    t.gpuLayersUsed = static_cast<std::uint64_t>(m_pool.layersUsed());
    t.gpuLayersFree = static_cast<std::uint64_t>(m_pool.layersFree());
    t.gpuEvictions = static_cast<std::uint64_t>(gpu.evictions);
    t.gpuUploads = static_cast<std::uint64_t>(gpu.uploads);
    t.gpuUploadBytes = gpu.bytesUploaded;
    t.gpuUploadsDeferred =
        m_frameCounts.gpuUploadsDeferred + static_cast<std::uint64_t>(gpu.uploadsDeferred);
    t.gpuRingStalls = static_cast<std::uint64_t>(gpu.ringStalls);
    t.loadsResident = m_frameCounts.loadsResident;
    t.loadLatencyP50Ms = m_recentLoads.percentile(50.0);
    t.loadLatencyP95Ms = m_recentLoads.percentile(95.0);
    t.loadLatencyP99Ms = m_recentLoads.percentile(99.0);
    t.diskReadBytes = io.bytesRead - m_bytesReadBefore;
    m_bytesReadBefore = io.bytesRead;
    t.storedBytesRead = io.storedBytesRead - m_storedBytesReadBefore;
    m_storedBytesReadBefore = io.storedBytesRead;
    const remote::RemoteStats http = io.http.since(m_httpBefore);
    m_httpBefore = io.http;
    t.httpRequests = http.requests;
    t.httpRetries = http.retries;
    t.httpFetched = http.fetched;
    t.httpFetchedBytes = http.fetchedBytes;
    t.httpNotModified = http.notModified;
    t.httpCacheHits = http.cacheHits;
    t.httpStaleServed = http.staleServed;
    t.faultsTotal = m_faults.size();
}

const TileFault* TileStreamer::faultOf(const io::PatchId& id) const {
    if (!m_failed.contains(id)) return nullptr;
    const auto fault = std::find_if(m_faults.begin(), m_faults.end(),
                                    [&](const TileFault& f) { return f.id == id; });
    return fault != m_faults.end() ? &*fault : nullptr;
}

int TileStreamer::releaseAllLayers() {
    int released = 0;
    for (int layer = 0; layer < m_pool.capacity(); ++layer) {
        const std::optional<io::PatchId> id = m_pool.patchOnLayer(layer);
        if (!id) continue;
        if (m_pool.isPinned(*id)) m_pool.unpin(*id);
        m_pool.release(*id);
        ++released;
    }
    return released;
}

bool TileStreamer::drain(std::chrono::milliseconds timeout) {
    for (auto& [id, load] : m_loads) {
        if (load.liveRequests > 0 && !load.cancelRequested) {
            m_io->cancel(id);
            load.cancelRequested = true;
        }
    }
    m_imagery->cancelAll();
    const auto deadline = Clock::now() + timeout;
    while (true) {
        takeCompletions();
        const io::IoThreadStats s = m_io->stats();
        if (s.queueDepth == 0 && s.inFlight == 0 && s.unpolled == 0) break;
        const auto now = Clock::now();
        if (now > deadline) return false;
        m_io->waitForCompletion(std::chrono::ceil<std::chrono::milliseconds>(deadline - now));
    }
    for (auto it = m_loads.begin(); it != m_loads.end();)
        it = it->second.liveRequests == 0 ? m_loads.erase(it) : std::next(it);
    m_imagery->forgetIdleLoads();
    return m_ledger.ended() == m_ledger.submitted &&
           m_imagery->ledger().ended() == m_imagery->ledger().submitted;
}

std::optional<std::string> TileStreamer::checkInvariants() const {
    if (auto broken = m_pool.checkInvariants()) return "GPU tile pool: " + *broken;
    if (auto broken = m_imagery->checkInvariants()) return *broken;
    if (m_cache.bytes() > m_cache.budgetBytes()) {
        return fmt::format("CPU tile cache holds {} bytes over its budget of {}", m_cache.bytes(),
                           m_cache.budgetBytes());
    }
    if (m_ledger.ended() > m_ledger.submitted) {
        return fmt::format("{} requests ended but only {} were made", m_ledger.ended(),
                           m_ledger.submitted);
    }
    for (const auto& [id, load] : m_loads) {
        if (load.liveRequests < 0) {
            return fmt::format("patch L{} ({}, {}) has {} live requests", id.level, id.x, id.y,
                               load.liveRequests);
        }
    }
    return std::nullopt;
}

}  // namespace terrain::runtime
