// The walk of terrain-inspect over a pyramid: every shard and every patch's info, level by
// level (counts, bytes, error statistics, Err_Appr nesting), and with `verify` every present
// patch read back and checked (PatchChecks.h).
#pragma once

#include "PatchChecks.h"

#include "terrain/pyramid/PyramidReader.h"

#include <cstdint>
#include <functional>
#include <vector>

namespace terrain::inspect {

struct LevelSummary {
    int level = 0;
    std::int64_t patchesX = 0, patchesY = 0;
    std::int64_t presentPatches = 0;  ///< counted in the shards' patchInfo
    std::int64_t shards = 0;
    std::int64_t missingShards = 0;  ///< absent or unreadable shard files
    std::uintmax_t bytes = 0;        ///< shard files on disk
    float minError = 0.0f, medianError = 0.0f, maxError = 0.0f;  ///< Err(P), present patches
};

struct Inspection {
    std::vector<LevelSummary> levels;  ///< root first
    std::vector<Problem> problems;
    std::int64_t patchesVerified = 0;  ///< read and checked (verify only)
    double verifySeconds = 0.0;        ///< time spent reading and checking patches
};

struct InspectOptions {
    bool verify = false;
    /// Called now and then with the fraction of patches done.
    std::function<void(double)> progress;
};

Inspection inspectPyramid(io::PyramidReader& reader, const InspectOptions& options);

}  // namespace terrain::inspect
