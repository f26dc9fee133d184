// StressChecks: the invariants terrain-stress checks every frame and at the end. Each
// returns the first violation it finds, described for a user, or nullopt.
#pragma once

#include "terrain/io/PatchIdHash.h"
#include "terrain/runtime/LodQuadtree.h"
#include "terrain/runtime/PatchSelection.h"
#include "terrain/runtime/TileStreamer.h"

#include <optional>
#include <span>
#include <string>
#include <vector>

namespace terrain::tools {

class StressChecks {
public:
    /// After a frame's LOD update and draw:
    /// - the streamer's own invariants (no layer both free and in use, one patch per layer,
    ///   CPU cache within its byte budget, no request ending twice);
    /// - the LOD tree's (leaves tile the domain exactly once, children only as complete
    ///   sets of resident, pinned patches);
    /// - every drawn patch resident on the layer the draw used (no draw references a
    ///   released layer);
    /// - drawn and culled patches tile the domain exactly once (no hole, no overlap);
    /// - bookkeeping bounded by the budgets (GPU layers, I/O queue no deeper than the
    ///   loads the LOD wants).
    std::optional<std::string> afterFrame(const runtime::TileStreamer& streamer,
                                          const runtime::LodQuadtree& tree,
                                          std::span<const runtime::PatchDraw> drawn,
                                          const runtime::LodUpdateStats& lod);

    /// After TileStreamer::drain(): every request ended exactly once (completed, cancelled
    /// or failed), in the streamer's ledger and the I/O thread's counters, and every
    /// failed patch was reported exactly once.
    static std::optional<std::string> afterDrain(const runtime::TileStreamer& streamer);

private:
    std::vector<io::PatchId> m_drawnSorted;  // reused every frame: no allocation once grown
};

}  // namespace terrain::tools
