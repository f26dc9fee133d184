// ImageryStreamer: the imagery tiles' way from the I/O thread to the GPU (issue 47), the
// imagery part of TileStreamer, which owns it and shares its IoThread: the same thread and
// request queue read heights and imagery in one priority order. Tiles wait in their own CPU
// cache (ImageryTileCache) and live on the GPU in one texture array (ImageryTilePool), under
// their own budgets. It is the draw's ImageryResidency.
//
// Frame protocol (render thread, GL context current), driven by TileStreamer:
//   beginFrame()          starts the pool's frame and the frame's counts;
//   takeCompletion(c)     for every imagery completion TileStreamer polled: into the cache;
//   gpuLayer()/want()     the draw's selection, any order, parents before children is best;
//   endFrame(t)           cancels requests wanted by no frame for cancelAfterFrames frames,
//                         fills the imagery telemetry columns.
//
// Never a hole: a tile is only ever drawn from its layer once uploaded (gpuLayer), and the
// layer of a tile used this frame is never taken for another; until a tile arrives the draw
// takes its finest resident ancestor. A tile that fails to read is reported once (faults())
// and never asked for again; a layer the I/O thread could not open is one fault, reported
// at creation, and none of its tiles is asked for.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/cache/ImageryTileCache.h"
#include "terrain/cache/ImageryTilePool.h"
#include "terrain/iothread/IoThread.h"
#include "terrain/iothread/TileKey.h"
#include "terrain/runtime/FrameTelemetry.h"
#include "terrain/runtime/ImageryResidency.h"
#include "terrain/runtime/LatencyHistogram.h"
#include "terrain/runtime/LatencyWindow.h"
#include "terrain/runtime/RecyclingLoadMap.h"

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <unordered_set>
#include <vector>

namespace terrain::runtime {

struct ImageryStreamerOptions {
    /// GPU memory of the imagery texture array (mips included); --imagery-gpu-mib.
    std::size_t gpuBytes = std::size_t{256} << 20;
    /// CPU imagery cache; --imagery-cache-mib.
    std::size_t cpuCacheBytes = std::size_t{128} << 20;
    /// Imagery bytes (mips included) uploaded per frame at most, apart from the heights'.
    std::size_t uploadBytesPerFrame = std::size_t{4} << 20;
    /// A request wanted by none of this many frames in a row is cancelled (the view moved
    /// on); more than one, so a tile the selection skips for a frame keeps its place.
    int cancelAfterFrames = 3;
    float maxAnisotropy = 16.0f;
};

struct ImageryFault {
    int layer = 0;
    io::PatchId id;       ///< the tile; the default PatchId for a layer that could not be opened
    std::string message;  ///< names the layer's file (or why the layer could not be opened)
};

/// Every imagery request made and how many have ended: after a drain, submitted ==
/// completed + failed + cancelled.
struct ImageryRequestLedger {
    std::uint64_t submitted = 0;
    std::uint64_t completed = 0;
    std::uint64_t failed = 0;
    std::uint64_t cancelled = 0;
    std::uint64_t ended() const { return completed + failed + cancelled; }
};

/// Render thread only (owns GL objects and uses the IoThread's owner side).
class ImageryStreamer final : public ImageryResidency {
public:
    /// For the imagery layers of `io` (its manifest's): creates the texture array when
    /// there is at least one layer. Errors: a GPU budget below one tile, a CPU cache that
    /// holds no tile. `io` must outlive the streamer.
    static Result<std::unique_ptr<ImageryStreamer>> create(io::IoThread& io,
                                                           const ImageryStreamerOptions& options);
    ~ImageryStreamer() override;
    ImageryStreamer(const ImageryStreamer&) = delete;
    ImageryStreamer& operator=(const ImageryStreamer&) = delete;

    // ImageryResidency.
    int imageryLayerCount() const override { return m_layerCount; }
    std::optional<int> gpuLayer(int layer, const io::PatchId& id) override;
    const io::ImageryTileInfo* tileInfo(int layer, const io::PatchId& id) const override;
    void want(int layer, const io::PatchId& id, float priority) override;

    void beginFrame();
    /// Takes one imagery completion (c.imageryLayer ≥ 0) that the owner polled.
    void takeCompletion(io::Completion& c);
    void endFrame(FrameTelemetry& telemetry);

    /// Cancels every live request (for a drain): they end as Cancelled or as they finished.
    void cancelAll();
    /// Forgets loads without a live request (after a drain).
    void forgetIdleLoads();

    /// The texture array the draw samples (GL_TEXTURE_2D_ARRAY, GL_SRGB8_ALPHA8, 256² tiles,
    /// kImageryTileMips mips); invalid when the pyramid has no imagery layer.
    const gl::Texture& texture() const { return m_pool.texture(); }
    /// Whether tile `id` of `layer` failed to read, or its layer could not be opened.
    bool hasFailed(int layer, const io::PatchId& id) const override {
        return m_layerUnopened[static_cast<std::size_t>(layer)] != 0 ||
               m_failed.contains(io::TileKey{id, layer});
    }
    const std::vector<ImageryFault>& faults() const { return m_faults; }
    const ImageryRequestLedger& ledger() const { return m_ledger; }
    /// First wanted → resident latency of every imagery load so far.
    const LatencyHistogram& loadLatencies() const { return m_loadLatencies; }
    const cache::ImageryTilePool& pool() const { return m_pool; }
    const cache::ImageryTileCache& cpuCache() const { return m_cache; }
    /// Tiles wanted and not yet resident (requested, or waiting for upload budget).
    std::size_t loadsOutstanding() const { return m_loads.size(); }
    /// Requests made and not yet ended.
    std::uint64_t requestsLive() const { return m_liveRequests; }

    /// The first broken invariant, or nullopt: the pool's own, the CPU cache within its
    /// budget, the ledger never ending more than it made, no negative live count.
    std::optional<std::string> checkInvariants() const;

private:
    using Clock = std::chrono::steady_clock;
    struct LoadState {
        Clock::time_point firstWanted;
        std::uint64_t firstWantedFrame = 0;
        std::uint64_t lastWantedFrame = 0;
        int liveRequests = 0;
        bool cancelRequested = false;
    };
    using LoadMap = RecyclingLoadMap<io::TileKey, LoadState, io::TileKeyHash>;

    ImageryStreamer(io::IoThread& io, cache::ImageryTilePool pool,
                    const ImageryStreamerOptions& options);
    LoadState& loadStateOf(const io::TileKey& key);
    bool uploadFromCache(const io::TileKey& key);

    io::IoThread& m_io;
    const int m_layerCount;
    const int m_cancelAfterFrames;
    cache::ImageryTileCache m_cache;
    cache::ImageryTilePool m_pool;

    std::uint64_t m_frame = 0;
    LoadMap m_loads;  // parks erased nodes: no allocation per request
    std::uint64_t m_liveRequests = 0;
    std::vector<std::uint8_t> m_layerUnopened;  // per layer: 1 when the I/O thread has no source
    std::unordered_set<io::TileKey, io::TileKeyHash> m_failed;
    std::vector<ImageryFault> m_faults;
    ImageryRequestLedger m_ledger;
    LatencyWindow m_recentLoads;
    LatencyHistogram m_loadLatencies;
    FrameTelemetry m_frameCounts;  // this frame's imagery counts so far
};

}  // namespace terrain::runtime
