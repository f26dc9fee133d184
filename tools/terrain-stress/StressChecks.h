// StressChecks: the invariants terrain-stress checks every frame and at the end. Each
// returns the first violation it finds, described for a user, or nullopt.
#pragma once

#include "terrain/pyramid/PatchIdHash.h"
#include "terrain/runtime/LodQuadtree.h"
#include "terrain/runtime/TerrainSession.h"
#include "terrain/runtime/TileStreamer.h"

#include <optional>
#include <span>
#include <string>
#include <vector>

namespace terrain::tools {

class StressChecks {
public:
    /// After a frame's LOD update and draw, on either surface:
    /// - the streamer's own invariants (no layer both free and in use, one patch per layer,
    ///   CPU cache within its byte budget, no request ending twice);
    /// - the LOD tree's (leaves tile the surface exactly once, children only as complete
    ///   sets, every patch with a tile of its own resident and pinned);
    /// - every drawn patch with a tile drawn from the resident layer of that tile (its own,
    ///   or its ancestor's for a virtual patch): no draw references a released layer;
    /// - no patch drawn twice or inside another; drawn and culled patches tile the surface
    ///   exactly once (no hole, no overlap);
    /// - bookkeeping bounded by the budgets (GPU layers, I/O queue no deeper than the
    ///   loads the LOD wants).
    std::optional<std::string> afterFrame(const runtime::TerrainSession& session,
                                          const runtime::LodUpdateStats& lod);

    /// After TileStreamer::drain(): every request ended exactly once (completed, cancelled
    /// or failed), in the streamer's ledger and the I/O thread's counters, and every
    /// failed patch was reported exactly once.
    static std::optional<std::string> afterDrain(const runtime::TileStreamer& streamer);

    /// Once the LOD let go of every patch it held: no GPU layer is pinned.
    static std::optional<std::string> afterLodReleased(const runtime::TileStreamer& streamer);

    /// After TileStreamer::releaseAllLayers() returned `released`: the whole pool is free.
    static std::optional<std::string> afterLayersReleased(const runtime::TileStreamer& streamer,
                                                          int released);

private:
    /// The streamer's own invariants and the budgets' bounds (layers, queue depth).
    static std::optional<std::string> streamerChecks(const runtime::TileStreamer& streamer);
    /// No id twice in m_drawnSorted (sorted here) and none inside another, looking up to
    /// the roots' level.
    std::optional<std::string> drawnOnceWithoutOverlap(int topLevel);

    std::vector<io::PatchId> m_drawnSorted;  // reused every frame: no allocation once grown
};

}  // namespace terrain::tools
