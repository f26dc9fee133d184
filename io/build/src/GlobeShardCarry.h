// GlobeShardCarry: what a globe region build's shard task hands to its parent shard's task and
// to the merge (GlobeShards.h): for each of its patches, the patch's key, its Err(P), its even
// samples, which are the parent's samples there, and per parent quad over it the interval of
// parent − source (the nested bound, Yusov & Shevtsov 2011, §4, signed and per quad); and the
// shard's summary (patches, largest Err(P), a finest shard's statistics of its
// source samples, the children shards it was built from). A temporary file of the staging
// folder (where ShardCarry.h's carryPath puts it), written to a temporary name and renamed.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/build/PyramidBuilder.h"
#include "terrain/pyramid/PyramidLayout.h"

#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

namespace terrain::io::detail {

struct GlobeShardCarry {
    std::string fingerprint;  // the plan's
    ShardId shard;
    // Summary, for the merge.
    std::int64_t patches = 0;
    float levelMaxError = 0.0f;
    double finestLargestQuantErrorM = 0.0;  // a lossy finest shard's largest rounding
    // A finest shard's source samples (those in its patches): each is in one shard.
    std::int64_t validSamples = 0, noDataSamples = 0;
    double minHeight = std::numeric_limits<double>::infinity();
    double maxHeight = -std::numeric_limits<double>::infinity();
    PyramidBuildPhases phases;
    double seconds = 0.0;
    std::vector<std::int64_t> childShards;  // x, y pairs of the finer shards it was built from
    // For the parent shard's task: per patch (its face-level key), its Err(P), its even samples
    // ((q/2 + 1)² of them, row-major, unrounded), and for each of the parent's quads over it
    // ((q/2)², row-major) the interval of parent − source over the samples there (low > high:
    // none; none at all where the parent is measured at the samples), GlobeShards.cpp's
    // carryToParents.
    std::vector<std::uint64_t> keys;
    std::vector<float> errors;
    std::vector<float> evenHeights;
    std::vector<std::uint8_t> evenValid;
    std::vector<float> parentLow, parentHigh;
};

Status writeGlobeCarry(const std::filesystem::path& path, const GlobeShardCarry& carry);

/// Reads a carry of patches of `quads` quads a side; without `whole` only its summary. Errors
/// name the file: missing, truncated, or not a globe carry.
Result<GlobeShardCarry> readGlobeCarry(const std::filesystem::path& path, bool whole, int quads);

}  // namespace terrain::io::detail
