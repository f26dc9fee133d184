// ImageryStreamer: completions into the CPU imagery cache, uploads from it within the frame
// budget, and a map of the tiles the draw wants, swept every frame for cancellations; the
// heights' TileStreamer scheme for imagery keys.
#include "terrain/runtime/ImageryStreamer.h"

#include "terrain/base/Assert.h"

#include <fmt/format.h>

#include <algorithm>
#include <iterator>
#include <utility>

namespace terrain::runtime {

Result<std::unique_ptr<ImageryStreamer>> ImageryStreamer::create(
    io::IoThread& io, const ImageryStreamerOptions& options) {
    TERRAIN_ASSERT(options.cancelAfterFrames >= 1, "ImageryStreamer: cancelAfterFrames < 1");
    cache::ImageryTilePool pool;
    if (io.imageryLayerCount() > 0) {
        // A tile the CPU cache cannot hold never reaches the GPU: the imagery would never show.
        if (options.cpuCacheBytes < cache::ImageryTileCache::kPresentTileBytes)
            return Error{
                fmt::format("a CPU imagery cache of {} bytes holds no tile; an imagery "
                            "tile needs {} bytes",
                            options.cpuCacheBytes, cache::ImageryTileCache::kPresentTileBytes)};
        auto created = cache::ImageryTilePool::create(
            {.budgetBytes = options.gpuBytes,
             .uploadBudgetBytesPerFrame = options.uploadBytesPerFrame,
             .maxAnisotropy = options.maxAnisotropy});
        if (!created) return created.error();
        pool = std::move(created).value();
    }
    return std::unique_ptr<ImageryStreamer>(new ImageryStreamer(io, std::move(pool), options));
}

ImageryStreamer::ImageryStreamer(io::IoThread& io, cache::ImageryTilePool pool,
                                 const ImageryStreamerOptions& options)
    : m_io(io),
      m_layerCount(io.imageryLayerCount()),
      m_cancelAfterFrames(options.cancelAfterFrames),
      m_cache(options.cpuCacheBytes),
      m_pool(std::move(pool)) {
    // The busiest frames' loads up front, so steady frames do not allocate.
    const auto capacity = static_cast<std::size_t>(m_pool.capacity());
    m_loads.reserve(2 * capacity);
    // A layer without a source would fail every tile the draw asks for: one fault instead.
    m_layerUnopened.assign(static_cast<std::size_t>(m_layerCount), 0);
    for (int layer = 0; layer < m_layerCount; ++layer) {
        if (io.imageryOpenError(layer).empty()) continue;
        m_layerUnopened[static_cast<std::size_t>(layer)] = 1;
        m_faults.push_back({layer, io::PatchId{}, std::string(io.imageryOpenError(layer))});
    }
}

ImageryStreamer::~ImageryStreamer() = default;

void ImageryStreamer::beginFrame() {
    ++m_frame;
    m_frameCounts = {};
    m_cache.resetCounters();
    if (m_layerCount > 0) m_pool.beginFrame();
}

void ImageryStreamer::takeCompletion(io::Completion& c) {
    TERRAIN_ASSERT(c.imageryLayer >= 0 && c.imageryLayer < m_layerCount,
                   "ImageryStreamer: a completion of no imagery layer");
    const io::TileKey key = c.key();
    const auto load = m_loads.find(key);
    if (load != m_loads.end()) --load->second.liveRequests;
    TERRAIN_ASSERT(m_liveRequests > 0, "ImageryStreamer: a completion without a request");
    --m_liveRequests;
    switch (c.status) {
        case io::CompletionStatus::Completed:
            ++m_ledger.completed;
            ++m_frameCounts.imageryRequestsCompleted;
            if (!c.imagery.info.present &&
                c.imagery.rgba.capacity() + c.imagery.mips.capacity() > 0) {
                // An absent tile read into a recycled buffer: the cache keeps its info only,
                // the buffer goes back to the I/O thread.
                io::ImageryTile absent{c.imagery.id, c.imagery.info, {}, {}};
                m_io.recycle(std::move(c.imagery));
                c.imagery = std::move(absent);
            }
            if (m_cache.insert(c.imageryLayer, std::move(c.imagery)) ==
                cache::TileCacheInsertResult::TooLarge)
                m_io.recycle(std::move(c.imagery));
            break;
        case io::CompletionStatus::Failed:
            ++m_ledger.failed;
            ++m_frameCounts.imageryRequestsFailed;
            // Reported once: a failed tile is never requested again.
            if (m_failed.insert(key).second)
                m_faults.push_back({c.imageryLayer, c.id, std::move(c.error)});
            if (load != m_loads.end() && load->second.liveRequests == 0) m_loads.erase(load);
            break;
        case io::CompletionStatus::Cancelled:
            ++m_ledger.cancelled;
            ++m_frameCounts.imageryRequestsCancelled;
            m_io.recycle(std::move(c.imagery));
            break;
    }
    // Tiles the cache dropped give their storage back to the I/O thread.
    while (auto evicted = m_cache.takeEvicted()) m_io.recycle(std::move(*evicted));
}

ImageryStreamer::LoadState& ImageryStreamer::loadStateOf(const io::TileKey& key) {
    return m_loads.findOrInsert(key, [&] {
        return LoadState{.firstWanted = Clock::now(),
                         .firstWantedFrame = m_frame,
                         .lastWantedFrame = m_frame,
                         .liveRequests = 0,
                         .cancelRequested = false};
    });
}

bool ImageryStreamer::uploadFromCache(const io::TileKey& key) {
    if (!m_pool.uploadBudgetLeft()) return false;
    if (!m_pool.allocateEvicting(key)) return false;  // every layer is drawn this frame
    const io::ImageryTile* tile = m_cache.find(key);
    TERRAIN_ASSERT(tile != nullptr, "ImageryStreamer: upload of a tile not in the CPU cache");
    if (!m_pool.upload(key, *tile)) {
        m_pool.release(key);
        return false;
    }
    return true;
}

std::optional<int> ImageryStreamer::gpuLayer(int layer, const io::PatchId& id) {
    TERRAIN_ASSERT(layer >= 0 && layer < m_layerCount, "ImageryStreamer: no such imagery layer");
    const io::TileKey key{id, layer};
    if (!m_pool.isResident(key)) return std::nullopt;
    m_pool.touch(key);
    return m_pool.layerOf(key);
}

const io::ImageryTileInfo* ImageryStreamer::tileInfo(int layer, const io::PatchId& id) const {
    TERRAIN_ASSERT(layer >= 0 && layer < m_layerCount, "ImageryStreamer: no such imagery layer");
    const io::TileKey key{id, layer};
    if (const io::ImageryTileInfo* info = m_pool.info(key)) return info;
    const io::ImageryTile* tile = m_cache.peek(key);
    return tile != nullptr ? &tile->info : nullptr;
}

void ImageryStreamer::want(int layer, const io::PatchId& id, float priority) {
    TERRAIN_ASSERT(layer >= 0 && layer < m_layerCount, "ImageryStreamer: no such imagery layer");
    const io::TileKey key{id, layer};
    if (m_pool.isResident(key)) {
        m_pool.touch(key);
        return;
    }
    if (hasFailed(layer, id)) return;
    LoadState& load = loadStateOf(key);
    load.lastWantedFrame = m_frame;
    if (const io::ImageryTile* tile = m_cache.peek(key)) {
        if (tile->info.present) {
            if (!uploadFromCache(key)) return;  // budget or layers used up: next frame
            const double ms =
                std::chrono::duration<double, std::milli>(Clock::now() - load.firstWanted).count();
            m_recentLoads.add(ms);
            m_loadLatencies.add(ms);
            ++m_frameCounts.imageryLoadsResident;
        }
        // Resident now, or known absent: nothing left to load.
        if (load.liveRequests == 0) m_loads.erase(m_loads.find(key));
        return;
    }
    // A live request is only re-prioritised: it may have finished, its completion waiting
    // for the next poll, and a second request would read the tile twice.
    if (load.liveRequests > 0 && !load.cancelRequested) {
        m_io.reprioritise(key, priority);
        return;
    }
    if (m_io.submit(key, priority)) {
        ++load.liveRequests;
        ++m_liveRequests;
        ++m_ledger.submitted;
        ++m_frameCounts.imageryRequestsMade;
    }
    load.cancelRequested = false;
}

void ImageryStreamer::endFrame(FrameTelemetry& t) {
    const auto patience = static_cast<std::uint64_t>(m_cancelAfterFrames);
    for (auto it = m_loads.begin(); it != m_loads.end();) {
        const auto next = std::next(it);
        LoadState& load = it->second;
        if (m_frame - load.lastWantedFrame >= patience) {
            if (load.liveRequests == 0) {
                m_loads.erase(it);
            } else if (!load.cancelRequested) {
                m_io.cancel(it->first);  // false when it finished already: polled next frame
                load.cancelRequested = true;
            }
        }
        it = next;
    }
    const cache::ImageryTilePoolFrameStats& gpu = m_pool.frameStats();
    t.imageryRequestsMade = m_frameCounts.imageryRequestsMade;
    t.imageryRequestsCancelled = m_frameCounts.imageryRequestsCancelled;
    t.imageryRequestsCompleted = m_frameCounts.imageryRequestsCompleted;
    t.imageryRequestsFailed = m_frameCounts.imageryRequestsFailed;
    t.imageryRequestsPending = m_liveRequests;
    t.imageryTilesResident = static_cast<std::uint64_t>(m_pool.layersUsed());
    t.imageryGpuBytes = m_pool.bytesUsed();
    t.imageryGpuUploads = static_cast<std::uint64_t>(gpu.uploads);
    t.imageryGpuUploadBytes = gpu.bytesUploaded;
    t.imageryGpuEvictions = static_cast<std::uint64_t>(gpu.evictions);
    t.imageryCpuCacheEntries = m_cache.entryCount();
    t.imageryCpuCacheBytes = m_cache.bytes();
    t.imageryLoadsResident = m_frameCounts.imageryLoadsResident;
    t.imageryLoadLatencyP50Ms = m_recentLoads.percentile(50.0);
    t.imageryLoadLatencyP95Ms = m_recentLoads.percentile(95.0);
    t.imageryFaultsTotal = m_faults.size();
}

void ImageryStreamer::cancelAll() {
    for (auto& [key, load] : m_loads) {
        if (load.liveRequests > 0 && !load.cancelRequested) {
            m_io.cancel(key);
            load.cancelRequested = true;
        }
    }
}

void ImageryStreamer::forgetIdleLoads() {
    for (auto it = m_loads.begin(); it != m_loads.end();)
        it = it->second.liveRequests == 0 ? m_loads.erase(it) : std::next(it);
}

std::optional<std::string> ImageryStreamer::checkInvariants() const {
    if (auto broken = m_pool.checkInvariants()) return "imagery tile pool: " + *broken;
    if (m_cache.bytes() > m_cache.budgetBytes())
        return fmt::format("CPU imagery cache holds {} bytes over its budget of {}",
                           m_cache.bytes(), m_cache.budgetBytes());
    if (m_ledger.ended() > m_ledger.submitted)
        return fmt::format("{} imagery requests ended but only {} were made", m_ledger.ended(),
                           m_ledger.submitted);
    if (m_ledger.submitted - m_ledger.ended() != m_liveRequests)
        return fmt::format("{} imagery requests live but the ledger says {}", m_liveRequests,
                           m_ledger.submitted - m_ledger.ended());
    for (const auto& [key, load] : m_loads)
        if (load.liveRequests < 0)
            return fmt::format("imagery layer {} tile L{} ({}, {}) has {} live requests",
                               key.imageryLayer, key.id.level, key.id.x, key.id.y,
                               load.liveRequests);
    return std::nullopt;
}

}  // namespace terrain::runtime
