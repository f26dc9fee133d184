// StressChecks: layer and coverage checks over the frame's draw list.
#include "StressChecks.h"

#include <fmt/format.h>

#include <algorithm>
#include <tuple>
#include <unordered_set>

namespace terrain::tools {
namespace {

std::string name(const io::PatchId& id) {
    return fmt::format("L{} ({}, {})", id.level, id.x, id.y);
}

}  // namespace

std::optional<std::string> StressChecks::afterFrame(const runtime::TerrainSession& session,
                                                    const runtime::LodUpdateStats& lod) {
    const runtime::TileStreamer& streamer = session.streamer();
    const runtime::Surface& surface = session.surface();
    if (auto broken = streamer.checkInvariants()) return broken;
    const cache::GpuTilePool& pool = streamer.pool();
    m_drawnSorted.clear();
    for (const runtime::PatchDraw& d : session.draws()) {
        m_drawnSorted.push_back(d.id);
        if (d.bare() && surface.drawsBareSurface()) continue;  // the bare ellipsoid: no tile
        if (d.layer < 0 || d.layer >= pool.capacity())
            return fmt::format("patch {} drawn from layer {}, outside the pool", name(d.id),
                               d.layer);
        const std::optional<io::PatchId> holder = pool.patchOnLayer(d.layer);
        if (!holder)
            return fmt::format("patch {} drawn from layer {}, which is free", name(d.id), d.layer);
        if (!(*holder == d.tileId) || !pool.isResident(d.tileId))
            return fmt::format("patch {} drawn from layer {} for the tile of {}, which holds {}",
                               name(d.id), d.layer, name(d.tileId), name(*holder));
    }
    if (auto broken = drawnOnceWithoutOverlap(surface.roots().front().level)) return broken;
    const std::uint64_t whole = surface.wholeCoverage();
    if (lod.drawn + lod.culled + lod.horizonCulled > 0 && lod.coverage != whole)
        return fmt::format("drawn and culled patches cover {:.12f} of the surface: {}",
                           double(lod.coverage) / double(whole),
                           lod.coverage < whole ? "a hole" : "an overlap");
    if (auto broken = session.tree().checkInvariants()) return "LOD tree: " + *broken;
    return streamerChecks(streamer);
}

std::optional<std::string> StressChecks::streamerChecks(const runtime::TileStreamer& streamer) {
    const cache::GpuTilePool& pool = streamer.pool();
    if (pool.layersUsed() > pool.capacity()) {
        return fmt::format("{} GPU layers used of {}", pool.layersUsed(), pool.capacity());
    }
    // The queue holds the heights' requests and the imagery's (one I/O thread for both).
    const io::IoThreadStats io = streamer.ioStats();
    const std::uint64_t imagery = streamer.imagery().requestsLive();
    if (io.queueDepth > streamer.loadsOutstanding() + imagery) {
        return fmt::format(
            "{} requests queued but the LOD wants only {} loads and the "
            "imagery {}",
            io.queueDepth, streamer.loadsOutstanding(), imagery);
    }
    return std::nullopt;
}

std::optional<std::string> StressChecks::drawnOnceWithoutOverlap(int topLevel) {
    const auto order = [](const io::PatchId& a, const io::PatchId& b) {
        return std::tie(a.level, a.y, a.x) < std::tie(b.level, b.y, b.x);
    };
    std::sort(m_drawnSorted.begin(), m_drawnSorted.end(), order);
    if (const auto twice = std::adjacent_find(m_drawnSorted.begin(), m_drawnSorted.end());
        twice != m_drawnSorted.end()) {
        return "patch " + name(*twice) + " drawn twice";
    }
    // No drawn patch may lie inside another drawn patch.
    for (const io::PatchId& id : m_drawnSorted) {
        io::PatchId up = id;
        while (up.level > topLevel) {
            up = {up.level - 1, up.x / 2, up.y / 2};
            if (std::binary_search(m_drawnSorted.begin(), m_drawnSorted.end(), up, order)) {
                return fmt::format("patches {} and {} overlap: both drawn", name(id), name(up));
            }
        }
    }
    return std::nullopt;
}

std::optional<std::string> StressChecks::afterDrain(const runtime::TileStreamer& streamer) {
    const runtime::TileRequestLedger& ledger = streamer.ledger();
    if (ledger.ended() != ledger.submitted) {
        return fmt::format("{} requests made but {} ended ({} completed, {} cancelled, {} failed)",
                           ledger.submitted, ledger.ended(), ledger.completed, ledger.cancelled,
                           ledger.failed);
    }
    const io::IoThreadStats io = streamer.ioStats();
    if (io.requested != io.completed + io.cancelled + io.failed || io.queueDepth != 0 ||
        io.inFlight != 0 || io.unpolled != 0) {
        return fmt::format(
            "I/O thread: {} requested, {} completed, {} cancelled, {} failed, {} "
            "queued, {} in flight, {} unpolled",
            io.requested, io.completed, io.cancelled, io.failed, io.queueDepth, io.inFlight,
            io.unpolled);
    }
    // One I/O thread serves the heights and the imagery: it saw both streamers' requests.
    const runtime::ImageryRequestLedger& imagery = streamer.imagery().ledger();
    if (imagery.submitted != imagery.ended()) {
        return fmt::format("{} imagery requests made but {} ended", imagery.submitted,
                           imagery.ended());
    }
    if (io.requested != ledger.submitted + imagery.submitted) {
        return fmt::format(
            "the I/O thread saw {} requests, the streamer made {} and the "
            "imagery {}",
            io.requested, ledger.submitted, imagery.submitted);
    }
    // Each failed patch is reported once (a patch may fail more than once: cancelled while
    // its read was ending, then requested again).
    std::unordered_set<io::PatchId, io::PatchIdHash> reported;
    for (const runtime::TileFault& fault : streamer.faults()) {
        if (!reported.insert(fault.id).second) {
            return fmt::format("patch L{} ({}, {}) reported as a fault twice", fault.id.level,
                               fault.id.x, fault.id.y);
        }
        if (!streamer.hasFailed(fault.id)) return "a reported fault is not marked as failed";
    }
    if (reported.size() > ledger.failed || (ledger.failed > 0 && reported.empty())) {
        return fmt::format("{} requests failed but {} faults were reported", ledger.failed,
                           reported.size());
    }
    return std::nullopt;
}

std::optional<std::string> StressChecks::afterLodReleased(const runtime::TileStreamer& streamer) {
    if (const int pinned = streamer.pool().pinnedCount(); pinned > 0)
        return fmt::format("{} GPU layers still pinned after the LOD let go", pinned);
    return std::nullopt;
}

std::optional<std::string> StressChecks::afterLayersReleased(const runtime::TileStreamer& streamer,
                                                             int released) {
    const cache::GpuTilePool& pool = streamer.pool();
    // Used and free layers add up to the capacity (the free list's invariant, checked
    // with the streamer's): all free is the one condition.
    if (pool.layersFree() != pool.capacity()) {
        return fmt::format("after releasing {} layers the pool has {} used and {} of {} free",
                           released, pool.layersUsed(), pool.layersFree(), pool.capacity());
    }
    return std::nullopt;
}

}  // namespace terrain::tools
