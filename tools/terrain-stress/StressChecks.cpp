// StressChecks: layer and coverage checks over the frame's draw list.
#include "StressChecks.h"

#include "terrain/pyramid/GlobeLayout.h"

#include <fmt/format.h>

#include <algorithm>
#include <tuple>
#include <unordered_set>

namespace terrain::tools {
namespace {

std::string name(const io::PatchId& id) {
    return fmt::format("L{} ({}, {})", id.level, id.x, id.y);
}

std::string globeName(const globe::GlobePatchId& id) {
    return fmt::format("face {} L{} ({}, {})", id.face, id.level, id.x, id.y);
}

}  // namespace

std::optional<std::string> StressChecks::afterFrame(const runtime::TileStreamer& streamer,
                                                    const runtime::LodQuadtree& tree,
                                                    std::span<const runtime::PatchDraw> drawn,
                                                    const runtime::LodUpdateStats& lod) {
    if (auto broken = streamer.checkInvariants()) return broken;
    const cache::GpuTilePool& pool = streamer.pool();
    const io::PyramidLayout& layout = streamer.layout();

    m_drawnSorted.clear();
    for (const runtime::PatchDraw& d : drawn) {
        if (d.layer < 0 || d.layer >= pool.capacity()) {
            return fmt::format("patch {} drawn from layer {}, outside the pool", name(d.id),
                               d.layer);
        }
        const std::optional<io::PatchId> holder = pool.patchOnLayer(d.layer);
        if (!holder) {
            return fmt::format("patch {} drawn from layer {}, which is free", name(d.id), d.layer);
        }
        if (!(*holder == d.id) || !pool.isResident(d.id)) {
            return fmt::format("patch {} drawn from layer {}, which holds {}", name(d.id), d.layer,
                               name(*holder));
        }
        m_drawnSorted.push_back(d.id);
    }
    if (auto broken = drawnOnceWithoutOverlap(0)) return broken;
    const std::uint64_t domain = runtime::finestPatchesCovered(layout, {0, 0, 0});
    const bool haveRoot = lod.drawn + lod.culled > 0;
    if (haveRoot && lod.coveredFinestPatches != domain) {
        return fmt::format("drawn and culled patches cover {} of the {} finest-level patches: {}",
                           lod.coveredFinestPatches, domain,
                           lod.coveredFinestPatches < domain ? "a hole" : "an overlap");
    }
    if (auto broken = tree.checkInvariants()) return "LOD tree: " + *broken;
    return streamerChecks(streamer);
}

std::optional<std::string> StressChecks::afterGlobeFrame(
    const runtime::TileStreamer& streamer, std::span<const runtime::GlobePatchDraw> drawn,
    const runtime::GlobeLodStats& lod) {
    if (auto broken = streamer.checkInvariants()) return broken;
    const cache::GpuTilePool& pool = streamer.pool();
    m_drawnSorted.clear();
    for (const runtime::GlobePatchDraw& d : drawn) {
        const io::PatchId id = io::layoutPatchOf(d.id);
        m_drawnSorted.push_back(id);
        if (d.layer < 0) continue;  // the bare ellipsoid: no tile
        const io::PatchId tile = io::layoutPatchOf(d.tileId);
        if (d.layer >= pool.capacity())
            return fmt::format("patch {} drawn from layer {}, outside the pool", globeName(d.id),
                               d.layer);
        const std::optional<io::PatchId> holder = pool.patchOnLayer(d.layer);
        if (!holder)
            return fmt::format("patch {} drawn from layer {}, which is free", globeName(d.id),
                               d.layer);
        if (!(*holder == tile) || !pool.isResident(tile))
            return fmt::format("patch {} drawn from layer {} for the tile of {}, which holds {}",
                               globeName(d.id), d.layer, globeName(d.tileId), name(*holder));
    }
    if (auto broken = drawnOnceWithoutOverlap(io::ManifestGlobe::kLevelOffset)) return broken;
    if (lod.drawn + lod.frustumCulled + lod.horizonCulled > 0 &&
        lod.coverage != runtime::GlobeLodStats::kWholeGlobeCoverage)
        return fmt::format(
            "drawn and culled patches cover {:.12f} of the globe's six faces: {}",
            double(lod.coverage) / double(runtime::GlobeLodStats::kWholeGlobeCoverage) * 6.0,
            lod.coverage < runtime::GlobeLodStats::kWholeGlobeCoverage ? "a hole" : "an overlap");
    return streamerChecks(streamer);
}

std::optional<std::string> StressChecks::streamerChecks(const runtime::TileStreamer& streamer) {
    const cache::GpuTilePool& pool = streamer.pool();
    if (pool.layersUsed() > pool.capacity()) {
        return fmt::format("{} GPU layers used of {}", pool.layersUsed(), pool.capacity());
    }
    const io::IoThreadStats io = streamer.ioStats();
    if (io.queueDepth > streamer.loadsOutstanding()) {
        return fmt::format("{} requests queued but the LOD wants only {} loads", io.queueDepth,
                           streamer.loadsOutstanding());
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
    if (io.requested != ledger.submitted) {
        return fmt::format("the I/O thread saw {} requests, the streamer made {}", io.requested,
                           ledger.submitted);
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
