// IoThread: reader threads, each a loop that pops the highest-priority request under the
// mutex, reads it (a heights patch or an imagery tile) with the mutex released, and files
// the outcome for poll().
#include "terrain/iothread/IoThread.h"

#include "terrain/pyramid/ParentTileCache.h"

#include "terrain/base/Assert.h"
#include "terrain/pyramid/ImageryMips.h"
#include "terrain/remote/RemoteFiles.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <thread>
#include <utility>

namespace terrain::io {

namespace {

/// The most records m_pool holds: recycle() and run() add one only below this.
std::size_t poolBound(const IoThreadOptions& options) {
    return options.maxUnpolled + static_cast<std::size_t>(options.readerThreads);
}

std::uint64_t recordBytes(const PatchRecord& r) {
    return static_cast<std::uint64_t>(r.heights.size() * sizeof(float) + r.valid.size() +
                                      r.blockErrors.size() * sizeof(BlockErrors) +
                                      sizeof(PatchInfo));
}

std::string tileName(const TileKey& key) {
    return fmt::format("tile L{} ({}, {})", key.id.level, key.id.x, key.id.y);
}

}  // namespace

int defaultReaderThreads() {
    return static_cast<int>(std::clamp(std::thread::hardware_concurrency(), 1U, 4U));
}

int defaultReaderThreads(std::string_view pyramidLocation) {
    if (!remote::isRemoteLocation(pyramidLocation)) return defaultReaderThreads();
    // An unreadable TERRAIN_HTTP_MAX_PER_HOST is reported when the pyramid is opened.
    const Result<remote::HttpOptions> http = remote::HttpOptions::fromEnvironment();
    const int perHost = http ? http.value().maxPerHost : remote::HttpOptions{}.maxPerHost;
    return std::max(defaultReaderThreads(), perHost);
}

Result<std::unique_ptr<IoThread>> IoThread::start(const std::filesystem::path& pyramidDir,
                                                  const IoThreadOptions& requested) {
    const IoThreadOptions options = requested.resolvedFor(pyramidDir.string());
    TERRAIN_ASSERT(options.maxUnpolled >= 1, "IoThread: maxUnpolled must be at least 1");
    TERRAIN_ASSERT(options.readerThreads >= 1, "IoThread: readerThreads must be at least 1");
    TERRAIN_ASSERT(options.faults.errorRate >= 0.0 && options.faults.errorRate <= 1.0,
                   "IoThread: errorRate outside [0, 1]");
    TERRAIN_ASSERT(options.faults.addedLatencyMs >= 0.0, "IoThread: negative addedLatencyMs");
    const auto parents = std::make_shared<ParentTileCache>(options.sharedParentCacheBytes());
    // A pyramid at a URL: each file is confirmed with the server once a run, whichever reader
    // opens it first.
    const auto run = std::make_shared<remote::RemoteRun>();
    std::vector<PyramidReader> readers;
    for (int i = 0; i < options.readerThreads; ++i) {
        auto reader = PyramidReader::open(pyramidDir, options.maxOpenShards, parents, run);
        if (!reader) return reader.error();
        readers.push_back(std::move(reader).value());
    }
    // Each imagery layer on its own: one that cannot be opened fails its own requests only.
    const PyramidManifest& manifest = readers.front().manifest();
    ImagerySources imagery;
    std::vector<std::string> openErrors;
    for (std::size_t k = 0; k < manifest.imagery.size(); ++k) {
        auto source = options.openImagery
                          ? options.openImagery(manifest, static_cast<int>(k))
                          : openImageryTiles(pyramidDir, manifest, manifest.imagery[k]);
        if (source && source.value() == nullptr)
            source = Error{fmt::format("{}: imagery layer \"{}\": no source", pyramidDir.string(),
                                       manifest.imagery[k].name)};
        if (source) {
            imagery.push_back(std::move(source).value());
            openErrors.emplace_back();
        } else {
            imagery.push_back(nullptr);
            openErrors.push_back(source.error().message);
        }
    }
    return std::unique_ptr<IoThread>(
        new IoThread(std::move(readers), std::move(imagery), std::move(openErrors), options));
}

IoThread::IoThread(std::vector<PyramidReader> readers, ImagerySources imagery,
                   std::vector<std::string> openErrors, const IoThreadOptions& options)
    : m_options(options),
      m_layout(readers.front().layout()),
      m_readers(std::move(readers)),
      m_imagery(std::move(imagery)),
      m_imageryOpenErrors(std::move(openErrors)) {
    // Up front, so recycling never allocates, and neither do the completions of reads
    // (their count is capped; only cancels beyond the cap can grow m_ready).
    m_pool.reserve(poolBound(m_options));
    m_imageryPool.reserve(poolBound(m_options));
    m_ready.reserve(m_options.maxUnpolled);
    m_inFlight.resize(m_readers.size());
    // Opening fetched (or confirmed) each reader's manifest: counted from the start.
    for (const PyramidReader& reader : m_readers) {
        m_readerCounted.push_back({reader.remoteStats(), 0});
        m_stats.http += m_readerCounted.back().http;
    }
    // Opening a layer at a URL fetched (or confirmed) its index: counted too.
    for (const std::unique_ptr<ImageryTileSource>& source : m_imagery) {
        m_imageryCounted.push_back(source ? ReadCost{source->remoteStats(), 0} : ReadCost{});
        m_stats.http += m_imageryCounted.back().http;
    }
    // Started last: the threads see every member constructed (thread start synchronises).
    m_threads.reserve(m_readers.size());
    for (std::size_t i = 0; i < m_readers.size(); ++i)
        m_threads.emplace_back([this, i](const std::stop_token& stop) { run(stop, i); });
}

IoThread::~IoThread() {
    // request_stop wakes m_wake through each stop token; a thread exits at its next wait.
    for (std::jthread& thread : m_threads) thread.request_stop();
    for (std::jthread& thread : m_threads) thread.join();
}

std::optional<IoThread::InFlight>* IoThread::liveInFlightLocked(const TileKey& key) {
    for (std::optional<InFlight>& slot : m_inFlight)
        if (slot && slot->key == key && !slot->cancelled) return &slot;
    return nullptr;
}

std::string_view IoThread::imageryOpenError(int layer) const {
    TERRAIN_ASSERT(layer >= 0 && layer < imageryLayerCount(), "IoThread: no such imagery layer");
    return m_imageryOpenErrors[static_cast<std::size_t>(layer)];
}

bool IoThread::submit(const TileKey& key, float priority) {
    TERRAIN_ASSERT(!std::isnan(priority), "IoThread::submit: NaN priority");
    TERRAIN_ASSERT(key.imageryLayer >= TileKey::kHeights && key.imageryLayer < imageryLayerCount(),
                   "IoThread::submit: no such imagery layer");
    {
        const std::lock_guard lock(m_mutex);
        if (liveInFlightLocked(key) != nullptr) return false;
        if (!m_pending.request(key, priority)) return false;  // re-prioritised
        addRequestTimeLocked(key, Clock::now());
        ++m_stats.requested;
    }
    m_wake.notify_all();
    return true;
}

bool IoThread::reprioritise(const TileKey& key, float priority) {
    TERRAIN_ASSERT(!std::isnan(priority), "IoThread::reprioritise: NaN priority");
    const std::lock_guard lock(m_mutex);
    if (!m_pending.contains(key)) return false;
    m_pending.request(key, priority);  // re-prioritises in place: allocates nothing
    return true;
}

bool IoThread::cancel(const TileKey& key) {
    {
        const std::lock_guard lock(m_mutex);
        // A pending request wins over an in-flight one: after cancel + submit of the same key
        // the pending one is the newer request.
        if (m_pending.cancel(key)) {
            // No record, no error text: creating it allocates nothing.
            Completion c;
            c.id = key.id;
            c.imageryLayer = key.imageryLayer;
            c.status = CompletionStatus::Cancelled;
            c.requestTime = takeRequestTimeLocked(key);
            c.completeTime = Clock::now();
            ++m_stats.cancelled;
            m_ready.push_back(std::move(c));
            return true;
        }
        std::optional<InFlight>* reading = liveInFlightLocked(key);
        if (reading == nullptr) return false;
        (*reading)->cancelled = true;  // its reader thread reports it when the read ends
    }
    m_wake.notify_all();  // cuts an injected latency short
    return true;
}

std::size_t IoThread::poll(std::vector<Completion>& out) {
    std::size_t count = 0;
    {
        const std::lock_guard lock(m_mutex);
        count = m_ready.size();
        for (Completion& c : m_ready) out.push_back(std::move(c));
        m_ready.clear();
    }
    if (count > 0) m_wake.notify_all();  // room for more results
    return count;
}

void IoThread::recycle(PatchRecord&& record) {
    const std::lock_guard lock(m_mutex);
    // Bounded: at most one buffer per result the cap allows, plus the one being read.
    if (m_pool.size() < poolBound(m_options)) m_pool.push_back(std::move(record));
}

void IoThread::recycle(ImageryTile&& tile) {
    const std::lock_guard lock(m_mutex);
    if (m_imageryPool.size() < poolBound(m_options)) m_imageryPool.push_back(std::move(tile));
}

bool IoThread::waitForCompletion(std::chrono::milliseconds timeout) {
    std::unique_lock lock(m_mutex);
    m_stateChanged.wait_for(lock, timeout, [&] {
        return !m_ready.empty() || (m_pending.empty() && m_inFlightCount == 0);
    });
    return !m_ready.empty();
}

bool IoThread::waitForState(const std::function<bool(const IoThreadStats&)>& reached,
                            std::chrono::milliseconds timeout) {
    std::unique_lock lock(m_mutex);
    return m_stateChanged.wait_for(lock, timeout, [&] { return reached(statsLocked()); });
}

IoThreadStats IoThread::stats() const {
    const std::lock_guard lock(m_mutex);
    return statsLocked();
}

IoThreadStats IoThread::statsLocked() const {
    IoThreadStats s = m_stats;
    s.queueDepth = m_pending.size();
    s.inFlight = m_inFlightCount;
    s.unpolled = m_ready.size();
    return s;
}

void IoThread::finishLocked(Completion&& completion) {
    switch (completion.status) {
        case CompletionStatus::Completed:
            ++m_stats.completed;
            m_stats.bytesRead += completion.imageryLayer == TileKey::kHeights
                                     ? recordBytes(completion.record)
                                     : completion.imagery.rgba.size();
            break;
        case CompletionStatus::Failed:
            ++m_stats.failed;
            break;
        case CompletionStatus::Cancelled:
            ++m_stats.cancelled;
            break;
    }
    m_ready.push_back(std::move(completion));
    m_stateChanged.notify_all();
}

void IoThread::addRequestTimeLocked(const TileKey& key, Clock::time_point time) {
    if (m_spareTimeNodes.empty()) {
        // A new high-water request count: the only time this map allocates or rehashes.
        m_requestTimes.emplace(key, time);
        const std::size_t nodeCount = m_requestTimes.size();  // nothing is parked now
        if (m_spareTimeNodes.capacity() < nodeCount)
            m_spareTimeNodes.reserve(std::max(nodeCount, 2 * m_spareTimeNodes.capacity()));
        return;
    }
    RequestTimes::node_type node = std::move(m_spareTimeNodes.back());
    m_spareTimeNodes.pop_back();
    node.key() = key;
    node.mapped() = time;
    m_requestTimes.insert(std::move(node));
}

IoThread::Clock::time_point IoThread::takeRequestTimeLocked(const TileKey& key) {
    RequestTimes::node_type node = m_requestTimes.extract(key);
    TERRAIN_ASSERT(!node.empty(), "IoThread: a pending request without its request time");
    const Clock::time_point time = node.mapped();
    m_spareTimeNodes.push_back(std::move(node));  // within capacity: see addRequestTimeLocked
    return time;
}

Status IoThread::readImagery(const TileKey& key, ImageryTile& out, const PyramidReader& reader,
                             ReadCost& cost) {
    const auto layer = static_cast<std::size_t>(key.imageryLayer);
    ImageryTileSource* source = m_imagery[layer].get();
    if (source == nullptr) return Error{m_imageryOpenErrors[layer]};
    {
        // Sources are not thread-safe (ImageryTileSource.h): one read at a time.
        const std::lock_guard sourceLock(m_imageryMutex);
        Status read = source->readTile(key.id, out);
        const ReadCost now{source->remoteStats(), source->storedBytesRead()};
        cost = now.since(m_imageryCounted[layer]);
        m_imageryCounted[layer] = now;
        if (!read) return read;
    }
    out.id = key.id;
    if (!out.info.present) {
        out.rgba.clear();  // keeps its capacity for the next tile
        out.mips.clear();
        return {};
    }
    // The pool uploads exactly one tile's texels: a source that hands out anything else is
    // a broken source, reported as this tile's failure rather than a crash on the GPU side.
    if (out.rgba.size() != kImageryTileBytes)
        return Error{fmt::format("{}: imagery layer \"{}\": {} has {} bytes of texels, not {}",
                                 reader.folder().string(), reader.manifest().imagery[layer].name,
                                 tileName(key), out.rgba.size(), kImageryTileBytes)};
    // The mips here, off the render thread: the pool only uploads them.
    makeImageryMips(out);
    return {};
}

// A patch the sparse globe does not store (asked for ahead of its parent) ends as an absent
// record rather than a failure, the reader's words in `absentWhy`: the streaming asks ahead
// for patches whose presence only their parent knows (issue 49). Telling an absent patch
// from a failed read costs nothing more (the shard is unlisted, or open with the patch's
// info) except after a failed read, whose shard is opened once more. A planar pyramid
// stores every patch of its layout: a read there fails or succeeds.
Status IoThread::readHeights(const PatchId& id, PatchRecord& out, PyramidReader& reader,
                             std::string& absentWhy) {
    Status read = reader.readPatch(id, out);
    if (read || !reader.manifest().globe) return read;
    const Result<PatchInfo> info = reader.patchInfo(id);
    if (!info || info.value().present) return read;  // a failure, not an absent patch
    out.id = id;
    out.info = PatchInfo{};
    out.heights.clear();  // keeps its capacity for the next patch
    out.valid.clear();
    out.blockErrors.clear();
    absentWhy = read.error().message;
    return {};
}

void IoThread::run(const std::stop_token& stop, std::size_t readerIndex) {
    PyramidReader& reader = m_readers[readerIndex];
    std::optional<InFlight>& inFlight = m_inFlight[readerIndex];
    const auto latency = std::chrono::duration_cast<Clock::duration>(
        std::chrono::duration<double, std::milli>(m_options.faults.addedLatencyMs));
    std::unique_lock lock(m_mutex);
    while (true) {
        const bool ready = m_wake.wait(lock, stop, [&] {
            return !m_pending.empty() && m_ready.size() + m_inFlightCount < m_options.maxUnpolled;
        });
        if (!ready) return;  // stop requested

        const auto request = m_pending.popHighest();
        const TileKey key = request->key();
        inFlight = InFlight{key, takeRequestTimeLocked(key), false};
        ++m_inFlightCount;
        m_stateChanged.notify_all();
        const bool imagery = key.isImagery();
        PatchRecord record;
        ImageryTile tile;
        if (!imagery && !m_pool.empty()) {
            record = std::move(m_pool.back());
            m_pool.pop_back();
        }
        if (imagery && !m_imageryPool.empty()) {
            tile = std::move(m_imageryPool.back());
            m_imageryPool.pop_back();
        }

        if (latency.count() > 0) {
            // Waits with the mutex released; a cancel or stop ends the wait early.
            m_wake.wait_for(lock, stop, latency, [&] { return inFlight->cancelled; });
            if (stop.stop_requested()) return;
        }

        const PatchId id = key.id;
        std::optional<Status> outcome;
        std::string absentWhy;
        bool injected = false;
        if (!inFlight->cancelled) {
            injected = !imagery && m_options.faults.failsRead(id);
            lock.unlock();
            ReadCost imageryCost;
            if (imagery) {
                outcome = readImagery(key, tile, reader, imageryCost);
            } else if (injected) {
                outcome =
                    Status(Error{fmt::format("{}: injected fault reading patch L{} ({}, {})",
                                             reader.folder().string(), id.level, id.x, id.y)});
            } else {
                outcome = readHeights(id, record, reader, absentWhy);
            }
            // This thread's reader: its counters are read on its own thread.
            const ReadCost readerNow{reader.remoteStats(), reader.storedBytesRead(),
                                     reader.parentReads()};
            lock.lock();
            const ReadCost cost = readerNow.since(m_readerCounted[readerIndex]);
            m_readerCounted[readerIndex] = readerNow;
            m_stats.http += cost.http;
            m_stats.http += imageryCost.http;
            m_stats.storedBytesRead += cost.storedBytes + imageryCost.storedBytes;
            m_stats.parentReads += cost.parentReads;
        }

        Completion c;
        c.id = id;
        c.imageryLayer = key.imageryLayer;
        c.requestTime = inFlight->requestTime;
        c.completeTime = Clock::now();
        if (inFlight->cancelled) {
            c.status = CompletionStatus::Cancelled;
        } else if (outcome->ok()) {
            c.status = CompletionStatus::Completed;
            if (imagery) {
                c.imagery = std::move(tile);
            } else {
                c.record = std::move(record);
                c.error = std::move(absentWhy);
            }
        } else {
            c.status = CompletionStatus::Failed;
            c.error = outcome->error().message;
            if (injected) ++m_stats.injectedFaults;
        }
        if (c.status != CompletionStatus::Completed) {
            if (imagery && m_imageryPool.size() < poolBound(m_options))
                m_imageryPool.push_back(std::move(tile));
            if (!imagery && m_pool.size() < poolBound(m_options))
                m_pool.push_back(std::move(record));
        }
        inFlight.reset();
        --m_inFlightCount;
        finishLocked(std::move(c));
    }
}

}  // namespace terrain::io
