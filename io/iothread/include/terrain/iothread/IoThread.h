// IoThread: the background I/O of streaming. Its reader threads (readerThreads; by default
// min(hardware threads, 4), for a pyramid at a URL at least the requests one host may have
// under way) take requests in priority order, each reads and decodes with its
// own PyramidReader, and all hand plain CPU records to the render thread, which never waits
// on disk (docs: DESIGN.md, "Streaming and caches"). One thread decoded only 650-1,900
// shuffled patches a second (issue 49): the decode, not the disk, limits it, so several
// decode at once. The same threads and the same request queue read the tiles of the
// pyramid's imagery layers (issue 47), one ImageryTileSource per layer: a request is keyed
// by TileKey (a PatchId alone is the heights'), and heights and imagery are served in one
// priority order.
//
// Imagery layers that cannot be opened: start() still succeeds, so the terrain draws without
// the layer; every request for that layer ends Failed with the error of opening it
// (imageryOpenError()), and the runtime keeps drawing what it had (issue 47: never a hole).
//
// Threading contract
// - The owner thread (the render thread) calls every public function; calls are serialised
//   by one mutex that is held only for queue and list operations, never during a read.
// - Each reader thread owns its PyramidReader (opened by start() before the threads begin)
//   and the record or imagery tile it is reading into. The imagery sources are shared by
//   the reader threads, one read at a time (m_imageryMutex, never held with m_mutex); the
//   mips are made outside it.
// - Every request (a submit that returned true) ends exactly once, as one Completion handed
//   out by poll(): Completed, Failed or Cancelled, whichever reader thread read it. A patch
//   a globe pyramid does not store, or an imagery tile a layer lacks, completes absent
//   (info.present false): the streaming asks ahead for patches whose presence only their
//   parent knows. A
//   request cancelled while it is being read ends as Cancelled (its record is recycled); a
//   request already finished but not yet polled is not cancellable and ends as it finished.
//   Requests still pending when the IoThread is destroyed end with it, without a Completion.
// - Backpressure: a reader thread starts a read only while the records being read (by all
//   of them) plus the completions waiting for poll() are fewer than maxUnpolled; otherwise
//   it waits for poll(). Cancelled completions are created on the owner thread and may
//   exceed the cap.
// - Order: reads start in priority order; with several reader threads they may end in
//   another (a tile read faster than one started before it), so only readerThreads = 1
//   hands completions out in priority order.
// - Buffers: recycle() returns a record's (an imagery tile's) storage to a pool the threads
//   read into (PyramidReader::readPatch(id, out), ImageryTileSource::readTile(id, out)), so
//   steady streaming does not allocate.
//
// Allocation on the owner thread: once the request count, the completions waiting for
// poll() and the caller's `out` vector have reached their high-water marks, submit(),
// cancel(), poll(out) and recycle() allocate nothing. Request bookkeeping reuses its nodes
// (TileRequestQueue, and here the request times), the completion list and the buffer pool
// keep their capacity, and a Cancelled Completion carries no record and no error text. The
// reader threads may allocate while they read (file access, failure messages).
#pragma once

#include "terrain/base/Result.h"
#include "terrain/iothread/FaultInjection.h"
#include "terrain/iothread/TileKey.h"
#include "terrain/iothread/TileRequestQueue.h"
#include "terrain/pyramid/ImageryTile.h"
#include "terrain/pyramid/ImageryTileSource.h"
#include "terrain/pyramid/PatchRecord.h"
#include "terrain/pyramid/PyramidLayout.h"
#include "terrain/pyramid/PyramidReader.h"
#include "terrain/remote/RemoteStats.h"

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <stop_token>
#include <string>
#include <string_view>
#include <thread>
#include <unordered_map>
#include <vector>

namespace terrain::io {

/// Opens the source of one imagery layer of the manifest (`index`: its place in
/// manifest.imagery) for the I/O thread.
using ImagerySourceOpener = std::function<Result<std::unique_ptr<ImageryTileSource>>(
    const PyramidManifest& manifest, int index)>;

/// The reader threads an IoThread starts by default: min(hardware threads, 4), at least 1.
/// Four: the decode scales to about the cores (issue 49's target, 2,500 shuffled patches a
/// second, needs two of today's), while each thread holds a PyramidReader (open shards and
/// a 4 MiB parent cache) and the render thread needs a core of its own.
int defaultReaderThreads();
/// The reader threads for the pyramid at `pyramidLocation`: defaultReaderThreads() for a
/// folder; for a URL, where a read waits on the network rather than on a core, at least as
/// many as the requests one host may have under way (remote::HttpOptions::maxPerHost,
/// TERRAIN_HTTP_MAX_PER_HOST, 6 by default), so that the reads ahead of a teleport travel
/// together instead of two round trips at a time on a 2-core machine.
int defaultReaderThreads(std::string_view pyramidLocation);

struct IoThreadOptions {
    std::size_t maxUnpolled = 8;  ///< cap on records being read + completions not yet polled
    /// Threads reading and decoding at once, each with its own PyramidReader; 0:
    /// defaultReaderThreads(the pyramid's location), as IoThread::start resolves it.
    int readerThreads = 0;
    int maxOpenShards = PyramidReader::kDefaultOpenShards;
    /// Decoded parents kept for their children (ParentTileCache.h), in one cache the reader
    /// threads share; 0: PyramidReader::kParentCacheBytes for each reader thread. A patch
    /// read in a shuffled order needs its parents, and each parent missed here is read again.
    std::size_t parentCacheBytes = 0;
    /// These options with readerThreads 0 replaced by defaultReaderThreads(pyramidLocation).
    IoThreadOptions resolvedFor(std::string_view pyramidLocation) const {
        IoThreadOptions resolved = *this;
        if (resolved.readerThreads == 0)
            resolved.readerThreads = defaultReaderThreads(pyramidLocation);
        return resolved;
    }
    /// The shared cache's bytes: parentCacheBytes, or its default for readerThreads (of
    /// resolved options).
    std::size_t sharedParentCacheBytes() const {
        return parentCacheBytes != 0
                   ? parentCacheBytes
                   : PyramidReader::kParentCacheBytes * static_cast<std::size_t>(readerThreads);
    }
    /// Injected errors are the heights' only (imagery has its own failures); an added
    /// latency delays every read.
    FaultInjection faults;
    /// How start() opens each imagery layer; empty: openImageryTiles (the layer's files, or
    /// the virtual planet's colours). Tests pass their own sources here.
    ImagerySourceOpener openImagery;
};

enum class CompletionStatus { Completed, Failed, Cancelled };

/// How one request ended.
struct Completion {
    using Clock = std::chrono::steady_clock;

    PatchId id;
    int imageryLayer = TileKey::kHeights;  ///< whose tile: the heights' or an imagery layer's
    CompletionStatus status = CompletionStatus::Completed;
    /// The heights' patch when Completed; recycle() it when done. Absent (info.present
    /// false, no heights) when a globe pyramid does not store the patch.
    PatchRecord record;
    ImageryTile imagery;  ///< an imagery tile and its mips when Completed (maybe absent)
    /// When Failed: names the file or "injected fault" and the patch. When Completed with
    /// an absent patch: the reader's words for that (naming the file and the patch).
    std::string error;
    Clock::time_point requestTime;   ///< the submit that created the request
    Clock::time_point completeTime;  ///< when the outcome was known

    TileKey key() const { return {id, imageryLayer}; }
};

/// A snapshot of the counters; requested == completed + failed + cancelled + queueDepth +
/// inFlight at any moment.
struct IoThreadStats {
    std::uint64_t requested = 0;  ///< submits that created a request
    std::uint64_t completed = 0;
    std::uint64_t failed = 0;
    std::uint64_t cancelled = 0;
    std::uint64_t injectedFaults = 0;  ///< failures caused by FaultInjection (also in failed)
    std::uint64_t bytesRead = 0;       ///< approximate: byte size of the completed records
    /// The payloads read (patches and imagery tiles), as stored in their files (compressed;
    /// PyramidReader::storedBytesRead, ImageryTileSource::storedBytesRead): what the view
    /// needed of the files, against which http.fetchedBytes is measured.
    std::uint64_t storedBytesRead = 0;
    /// Parents read again only to decode a child predicted from them, since they were no
    /// longer in the readers' shared ParentTileCache (PyramidReader::parentReads).
    std::uint64_t parentReads = 0;
    /// For a pyramid at a URL, what its readers' fetches cost (RemoteFiles.h), all readers
    /// and imagery layers together; zero for a folder.
    remote::RemoteStats http;
    std::size_t queueDepth = 0;        ///< pending requests
    std::size_t inFlight = 0;          ///< requests being read (0 to readerThreads)
    std::size_t unpolled = 0;          ///< completions waiting for poll()
};

class IoThread {
public:
    /// Opens the pyramid (its manifest) and its imagery layers and starts the thread. An
    /// imagery layer that cannot be opened is no error here (see imageryOpenError()).
    /// Owner thread.
    static Result<std::unique_ptr<IoThread>> start(const std::filesystem::path& pyramidDir,
                                                   const IoThreadOptions& options = {});

    /// Stops the threads: a read in progress finishes (an injected latency is cut short),
    /// pending requests are dropped. Owner thread.
    ~IoThread();
    IoThread(const IoThread&) = delete;
    IoThread& operator=(const IoThread&) = delete;

    /// Requests `key` (higher priority first; every frame is fine; a PatchId alone is the
    /// heights' patch, an imagery key's layer must be below imageryLayerCount()). A pending
    /// request for `key` is re-prioritised instead and false is returned; so is a request
    /// being read (which ignores the new priority). Returns true when a new request was
    /// created, which will end in exactly one Completion. `priority` must not be NaN.
    /// Owner thread.
    bool submit(const TileKey& key, float priority);

    /// Changes the priority of the pending request for `key` and returns true; returns false
    /// and does nothing when `key` has no pending request (never requested, being read, or
    /// finished). Unlike submit() it never creates a request. Owner thread.
    bool reprioritise(const TileKey& key, float priority);

    /// Cancels the pending or in-progress request for `key`; it will end as a Cancelled
    /// Completion. False when `key` has no live request. Owner thread.
    bool cancel(const TileKey& key);

    /// Appends every finished Completion to `out` and returns how many; never waits on disk.
    /// Owner thread.
    std::size_t poll(std::vector<Completion>& out);

    /// Returns a record's storage to the pool the thread reads into. Owner thread.
    void recycle(PatchRecord&& record);
    /// Returns an imagery tile's storage to the pool the thread reads imagery into.
    /// Owner thread.
    void recycle(ImageryTile&& tile);

    /// Waits until a Completion is ready for poll(), or until the threads have nothing to
    /// read (no pending request, none in flight), or `timeout`; true when one is ready.
    /// For callers that must wait for streaming (settling a view, draining at shutdown,
    /// tests): they wake on the outcome instead of sleeping. Owner thread.
    bool waitForCompletion(std::chrono::milliseconds timeout);

    /// Waits until `reached(stats())` holds, or `timeout`; true when it holds. The state is
    /// looked at on entry and whenever a thread starts or ends a read, so a caller waits
    /// for a state of the thread (a read under way, the results cap reached) on the event
    /// that makes it, never by sleeping. `reached` runs with the lock held: it must only look
    /// at its argument. Owner thread.
    bool waitForState(const std::function<bool(const IoThreadStats&)>& reached,
                      std::chrono::milliseconds timeout);

    IoThreadStats stats() const;  ///< Owner thread (any thread is safe).
    const PyramidLayout& layout() const { return m_layout; }                  ///< Any thread.
    int readerThreads() const { return static_cast<int>(m_readers.size()); }  ///< Any thread.
    /// The manifest's imagery layers (opened or not). Any thread.
    int imageryLayerCount() const { return static_cast<int>(m_imageryOpenErrors.size()); }
    /// Why imagery layer `layer` could not be opened (its requests end Failed with this), or
    /// empty when it was. Any thread.
    std::string_view imageryOpenError(int layer) const;

private:
    using Clock = Completion::Clock;

    // A reader thread's read: its key, and whether it was cancelled meanwhile.
    struct InFlight {
        TileKey key;
        Clock::time_point requestTime;
        bool cancelled = false;
    };
    using InFlightSlots = std::vector<std::optional<InFlight>>;  // one per reader thread

    using RequestTimes = std::unordered_map<TileKey, Clock::time_point, TileKeyHash>;
    using ImagerySources = std::vector<std::unique_ptr<ImageryTileSource>>;

    IoThread(std::vector<PyramidReader> readers, ImagerySources imagery,
             std::vector<std::string> openErrors, const IoThreadOptions& options);
    // Reader thread `reader`, m_mutex released.
    // What a read cost: over HTTP, of the files (stored payload bytes), and the parents it
    // read again.
    struct ReadCost {
        remote::RemoteStats http;
        std::uint64_t storedBytes = 0;
        std::uint64_t parentReads = 0;
        ReadCost since(const ReadCost& before) const {
            return {http.since(before.http), storedBytes - before.storedBytes,
                    parentReads - before.parentReads};
        }
    };
    // `cost` gets what the read cost (the layer's counters since its last read).
    Status readImagery(const TileKey& key, ImageryTile& out, const PyramidReader& reader,
                       ReadCost& cost);
    static Status readHeights(const PatchId& id, PatchRecord& out, PyramidReader& reader,
                              std::string& absentWhy);
    IoThreadStats statsLocked() const;
    std::optional<InFlight>* liveInFlightLocked(const TileKey& key);  // not cancelled, or null
    void run(const std::stop_token& stop, std::size_t reader);
    void finishLocked(Completion&& completion);
    void addRequestTimeLocked(const TileKey& key, Clock::time_point time);
    Clock::time_point takeRequestTimeLocked(const TileKey& key);  // parks its node

    const IoThreadOptions m_options;
    const PyramidLayout m_layout;
    // One per reader thread: m_readers[i] is thread i's only, after start().
    std::vector<PyramidReader> m_readers;
    // Per imagery layer: its source (read under m_imageryMutex, after start()), null where
    // it could not be opened, and then why (immutable after start()).
    const ImagerySources m_imagery;
    std::mutex m_imageryMutex;  // one imagery read at a time; never taken with m_mutex held
    // Per layer: its source's counters when last added to m_stats (guarded by
    // m_imageryMutex).
    std::vector<ReadCost> m_imageryCounted;
    const std::vector<std::string> m_imageryOpenErrors;

    mutable std::mutex m_mutex;
    std::condition_variable_any m_wake;      // work, room for results, cancel, or stop
    std::condition_variable m_stateChanged;  // a read started, or a completion was filed
    TileRequestQueue m_pending;
    RequestTimes m_requestTimes;  // pending
    // Nodes of request times that ended, for the next submits; the capacity covers every
    // node ever allocated, so parking one (on either thread) never allocates.
    std::vector<RequestTimes::node_type> m_spareTimeNodes;
    InFlightSlots m_inFlight;  // slot i: reader thread i's read, if any
    // Slot i: reader i's counters when last added to m_stats (guarded by m_mutex).
    std::vector<ReadCost> m_readerCounted;
    std::size_t m_inFlightCount = 0;
    std::vector<Completion> m_ready;         // finished, not yet polled
    std::vector<PatchRecord> m_pool;         // recycled record storage; reserved to its bound
    std::vector<ImageryTile> m_imageryPool;  // recycled imagery storage; the same bound
    IoThreadStats m_stats;                   // queueDepth / inFlight / unpolled filled by stats()

    std::vector<std::jthread> m_threads;  // last: stop and join before the members above go
};

}  // namespace terrain::io
