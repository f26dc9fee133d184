// PyramidShards: a planar pyramid built one shard at a time (docs/pyramid-format.md,
// "Region builds"), so that peak memory is one shard's whatever the raster's width, and so
// that the shards can be built by many processes on many machines (tools/cluster).
//
// The build is a map over the finest level's shards, then a reduction up the levels: a
// finest shard is built from the source window it covers, a coarser one from the finer
// shards beneath it (their even samples and nested error bounds, Yusov & Shevtsov 2011, §4),
// never from the source. Each task writes its shard and a "carry" file (what the coarser
// level needs) into the staging folder "<output>.parts", each to a temporary name renamed
// into place, so a task that is run again, or twice at once, writes the same bytes and
// leaves nothing half-written. The merge writes the manifest once every shard is in place,
// and moves the folder to the output in one rename. The files are identical to buildPyramid's,
// byte for byte (the manifest's build.seconds aside).
#pragma once

#include "terrain/base/Result.h"
#include "terrain/source/DemReader.h"
#include "terrain/build/PyramidBuilder.h"
#include "terrain/pyramid/PyramidLayout.h"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace terrain::io {

/// "<output>.parts": where the shards of a region build of `output` are gathered.
std::filesystem::path shardStagingFolder(const std::filesystem::path& output);

struct ShardPlan {
    PyramidLayout layout;
    std::filesystem::path staging;
    /// The source and the options that decide the shards' bytes; every task and the merge
    /// check theirs against it, so shards of different builds never mix.
    std::string fingerprint;
};

/// Checks the source and options (a planar build; a rotated source is refused), creates the
/// staging folder with its plan, or checks that an existing one was started with the same
/// source and options. Idempotent.
Result<ShardPlan> planPyramidShards(DemReader& reader, const std::filesystem::path& output,
                                    const PyramidBuildOptions& options);

/// The shards of `level + 1` that a shard of `level` is built from: x and y in
/// [2s − 1, 2s + 2], where they exist (its children and the neighbours its apron reaches).
std::vector<ShardId> shardInputs(const PyramidLayout& layout, const ShardId& shard);

struct ShardBuildSummary {
    ShardId shard;
    std::int64_t patches = 0;
    std::uint64_t bytes = 0;  ///< the shard file
    double seconds = 0.0;
};

/// Builds one shard of the plan's pyramid into the staging folder. A shard below the finest
/// level needs its shardInputs built first (an Error names the one missing). Running it
/// again rewrites the same bytes. Memory: one shard's band, records and samples
/// (planarShardBytes), whatever the raster's width.
Result<ShardBuildSummary> buildPyramidShard(DemReader& reader, const std::filesystem::path& output,
                                            const ShardId& shard,
                                            const PyramidBuildOptions& options);

/// Bytes a shard task needs at most, about; a task refuses a budget below it.
std::uint64_t planarShardBytes(const PyramidLayout& layout);

/// Once every shard of every level is built: checks them (present, of this plan), writes the
/// manifest and moves the staging folder to `output` (an existing one only with
/// options.overwrite). Refuses, naming the first missing or foreign shard, and writes
/// nothing, when the build is incomplete or mixed.
Result<PyramidBuildSummary> mergePyramidShards(DemReader& reader,
                                               const std::filesystem::path& output,
                                               const PyramidBuildOptions& options);

/// The whole pyramid as a region build in this process, one shard after another: the
/// single-machine case of a distributed build, and how buildPyramid builds a raster too
/// wide for a band across it within the memory budget. A failed build removes its staging
/// folder.
Result<PyramidBuildSummary> buildPyramidByShards(DemReader& reader,
                                                 const std::filesystem::path& output,
                                                 const PyramidBuildOptions& options);

}  // namespace terrain::io
