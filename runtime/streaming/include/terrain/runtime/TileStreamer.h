// TileStreamer: the streaming path of one pyramid, from disk to the GPU (DESIGN.md,
// "Streaming and caches"): the background IoThread reads what the LOD asks for, decoded
// tiles wait in the CPU TileCache, and the GpuTilePool uploads them within a per-frame
// byte budget, evicting layers the current view does not use.
//
// Frame protocol (render thread, GL context current):
//   beginFrame()  takes finished reads into the CPU cache, starts the pool's frame;
//   acquire(...)  for every patch the LOD wants, parents before children;
//   endFrame(t)   cancels requests no longer wanted, fences uploads, fills telemetry.
//
// Faults: a tile that fails to read is reported once (faults()), counted, and never asked
// for again; acquire() keeps answering null for it, so the LOD keeps drawing its nearest
// resident ancestor and no hole appears.
//
// Imagery (issue 47): the pyramid's imagery layers stream through the same I/O thread and
// request queue, into their own CPU cache and GPU texture array (ImageryStreamer, owned here
// and driven by the same beginFrame/endFrame); imagery() is the draw's ImageryResidency.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/cache/GpuTilePool.h"
#include "terrain/cache/TileCache.h"
#include "terrain/iothread/IoThread.h"
#include "terrain/pyramid/NativeTiles.h"
#include "terrain/pyramid/PatchIdHash.h"
#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/remote/RemoteStats.h"
#include "terrain/runtime/FrameTelemetry.h"
#include "terrain/runtime/ImageryStreamer.h"
#include "terrain/runtime/LatencyHistogram.h"
#include "terrain/runtime/LatencyWindow.h"
#include "terrain/runtime/RecyclingLoadMap.h"
#include "terrain/runtime/TileResidency.h"

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <unordered_set>
#include <vector>

namespace terrain::runtime {

struct TileStreamerOptions {
    std::size_t cpuCacheBytes = std::size_t{64} << 20;
    /// GPU layers of the tile pool; the pool's memory is gpuLayers × bytesPerLayer.
    int gpuLayers = 256;
    std::size_t uploadBytesPerFrame = std::size_t{4} << 20;
    /// Time a frame may spend uploading tiles, beside the byte budget (issue 49: a budget in
    /// milliseconds for slow drivers and slow frames); 0: none. A frame always uploads at
    /// least one tile, so streaming never stalls.
    double uploadMsPerFrame = 0.0;
    /// Read the tiles the LOD expects to want soon (TileResidency::prefetch) into the CPU
    /// cache; false: only what it wants now, so refining takes a frame a level.
    bool prefetch = true;
    /// The I/O thread's options; its maxUnpolled is raised to the tiles uploadBytesPerFrame
    /// holds (ioOptionsFor), so the I/O side never caps a frame below its upload budget.
    io::IoThreadOptions io;
    /// The imagery layers' budgets (used only when the pyramid has imagery).
    ImageryStreamerOptions imagery;
};

struct TileFault {
    io::PatchId id;
    std::string message;  ///< names the shard file (or the injected fault) and the patch
};

/// A patch that became resident on the GPU after the LOD first wanted it.
struct TileLoad {
    io::PatchId id;
    double latencyMs = 0.0;           ///< first wanted → resident (uploaded)
    std::uint64_t latencyFrames = 0;  ///< the same in frames (0: resident in the same frame)
};

/// Every request the streamer made and how many have ended: after drain(),
/// submitted == completed + failed + cancelled.
struct TileRequestLedger {
    std::uint64_t submitted = 0;
    std::uint64_t completed = 0;
    std::uint64_t failed = 0;
    std::uint64_t cancelled = 0;
    std::uint64_t ended() const { return completed + failed + cancelled; }
};

/// Render thread only (owns GL objects and the IoThread's owner side). In steady state
/// (no faults, the I/O thread's own reads aside) a frame allocates no memory. Serves the
/// LOD as its TileResidency: resident means uploaded to a layer of the GPU pool.
class TileStreamer final : public TileResidency {
public:
    /// Opens the pyramid, starts the I/O thread, creates the GPU pools (heights, and
    /// imagery when the pyramid has imagery layers). Errors name the pyramid or the budget
    /// that does not fit. An imagery layer that cannot be opened is no error: its tiles fail
    /// (imagery().faults()) and the terrain draws without it.
    static Result<std::unique_ptr<TileStreamer>> open(const std::filesystem::path& pyramid,
                                                      const TileStreamerOptions& options);
    ~TileStreamer() override;
    TileStreamer(const TileStreamer&) = delete;
    TileStreamer& operator=(const TileStreamer&) = delete;

    const io::PyramidManifest& manifest() const { return m_manifest; }
    const io::PyramidLayout& layout() const { return m_manifest.layout; }
    /// A globe pyramid's native grids (their finest tiles stream by their native tile ids,
    /// NativeTiles.h); none for another pyramid.
    const std::vector<io::NativeGridManifest>& nativeGrids() const { return m_nativeGrids; }

    void beginFrame();

    // TileResidency. acquire(): resident on the GPU (possibly uploaded just now from the
    // CPU cache), which also keeps its layer from eviction this frame; or on its way:
    // requested from disk with `priority` unless it is in the CPU cache waiting for
    // upload budget, or it failed before. pin(): GpuTilePool::pin.
    const io::PatchInfo* acquire(const io::PatchId& id, float priority) override;
    void prefetch(const io::PatchId& id, float priority) override;
    int layerOf(const io::PatchId& id) const override;
    bool hasFailed(const io::PatchId& id) const override { return m_failed.contains(id); }
    bool knownAbsent(const io::PatchId& id) const override { return m_absent.contains(id); }
    void pin(const io::PatchId& id) override { m_pool.pin(id); }
    void unpin(const io::PatchId& id) override { m_pool.unpin(id); }
    int capacity() const override { return m_pool.capacity(); }
    const io::PatchInfo* residentInfo(const io::PatchId& id) const override {
        return m_pool.info(id);
    }
    bool isPinned(const io::PatchId& id) const override { return m_pool.isPinned(id); }
    std::optional<io::SampleRises> residentSampleRises(const io::PatchId& id) const override {
        return m_pool.sampleRises(id);
    }

    void endFrame(FrameTelemetry& telemetry);

    /// Waits until a read has finished (taken by the next beginFrame), the I/O thread has
    /// nothing left to read, or `timeout`: for callers that must wait for streaming
    /// (settling a view, tests) instead of sleeping; true when a read has finished (heights
    /// or imagery). Between frames.
    bool waitForReads(std::chrono::milliseconds timeout) {
        return m_io->waitForCompletion(timeout);
    }

    /// Cancels every request (heights and imagery) and waits until all have ended; false on
    /// timeout. For shutdown checks: afterwards ledger() and imagery().ledger() must balance.
    bool drain(std::chrono::milliseconds timeout);

    /// The imagery layers' streaming: the draw's ImageryResidency. Render thread only.
    ImageryStreamer& imagery() { return *m_imagery; }
    const ImageryStreamer& imagery() const { return *m_imagery; }
    /// The imagery texture array the draw samples (ImageryStreamer::texture()); invalid when
    /// the pyramid has no imagery layer.
    const gl::Texture& imageryTiles() const { return m_imagery->texture(); }

    const std::vector<TileFault>& faults() const { return m_faults; }
    /// The fault of `id` if it failed to read; nullptr otherwise.
    const TileFault* faultOf(const io::PatchId& id) const;
    const TileRequestLedger& ledger() const { return m_ledger; }
    /// Request → resident latency of every load so far.
    const LatencyHistogram& loadLatencies() const { return m_loadLatencies; }
    /// Called for every load as it becomes resident (render thread, inside acquire()), e.g.
    /// to keep latency statistics of one part of a run. Must not call back into the
    /// streamer.
    void setLoadObserver(std::function<void(const TileLoad&)> observer) {
        m_loadObserver = std::move(observer);
    }
    const cache::GpuTilePool& pool() const { return m_pool; }
    const cache::TileCache& cpuCache() const { return m_cache; }
    /// Gives back every GPU layer (pinned ones too): the end of a session, after drain(), so
    /// a program can check the pool got every layer back. Nothing may be drawn from the
    /// streamer's tiles afterwards without selecting again. Returns the layers released.
    int releaseAllLayers();
    io::IoThreadStats ioStats() const { return m_io->stats(); }
    /// Patches requested or waiting for upload (bounded by what the LOD wants).
    std::size_t loadsOutstanding() const { return m_loads.size(); }

    /// The first broken invariant of the streamer and its pool, or nullopt: the pool's
    /// own, the CPU cache within its budget, the ledger never ending more than it made.
    std::optional<std::string> checkInvariants() const;

private:
    using Clock = std::chrono::steady_clock;
    struct LoadState {
        Clock::time_point firstWanted;
        std::uint64_t firstWantedFrame = 0;
        std::uint64_t lastWantedFrame = 0;
        int liveRequests = 0;  // submitted and not yet ended
        bool cancelRequested = false;
        bool aheadOnly = false;  // asked for by prefetch() only, not yet by acquire()
    };
    using LoadMap = RecyclingLoadMap<io::PatchId, LoadState, io::PatchIdHash>;

    TileStreamer(io::PyramidManifest manifest, std::unique_ptr<io::IoThread> io,
                 std::unique_ptr<ImageryStreamer> imagery, cache::GpuTilePool pool,
                 const TileStreamerOptions& options);
    /// `options.io` with maxUnpolled raised to a frame's upload budget in tiles of `pool`.
    static io::IoThreadOptions ioOptionsFor(const TileStreamerOptions& options,
                                            const cache::GpuTilePool& pool);
    bool uploadFromCache(const io::PatchId& id);
    // The load of `id`, made fresh (wanted from now) if there was none; `inserted` then says so.
    LoadState& loadStateOf(const io::PatchId& id, bool* inserted = nullptr);
    // Makes sure `id` is on its way at `priority` (acquire's and prefetch's requests).
    void request(const io::PatchId& id, LoadState& load, float priority);
    void takeCompletions();
    void takeAbsent(io::Completion& c, LoadMap::iterator load);

    io::PyramidManifest m_manifest;
    std::vector<io::NativeGridManifest> m_nativeGrids;
    std::unique_ptr<io::IoThread> m_io;
    std::unique_ptr<ImageryStreamer> m_imagery;  // uses m_io: declared after it, gone before
    cache::TileCache m_cache;
    cache::GpuTilePool m_pool;

    std::uint64_t m_frame = 0;
    LoadMap m_loads;                            // parks erased nodes: no allocation per request
    std::vector<io::Completion> m_completions;  // poll() target, capacity kept
    std::unordered_set<io::PatchId, io::PatchIdHash> m_failed;
    /// Patches read ahead and found absent (takeAbsent), at most kMaxKnownAbsent.
    static constexpr std::size_t kMaxKnownAbsent = 1U << 16;
    std::unordered_set<io::PatchId, io::PatchIdHash> m_absent;
    std::vector<TileFault> m_faults;
    TileRequestLedger m_ledger;

    LatencyWindow m_recentLoads;
    LatencyHistogram m_loadLatencies;
    std::function<void(const TileLoad&)> m_loadObserver;
    FrameTelemetry m_frameCounts;  // this frame's counts so far
    const double m_uploadMsPerFrame;
    const bool m_prefetch;
    double m_uploadMsThisFrame = 0.0;  // time in GpuTilePool::upload this frame
    std::uint64_t m_bytesReadBefore = 0;
    std::uint64_t m_storedBytesReadBefore = 0;
    remote::RemoteStats m_httpBefore;  // the I/O thread's HTTP counters at the last endFrame
};

}  // namespace terrain::runtime
