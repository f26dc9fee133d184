// PyramidShards: a pyramid built one shard at a time (docs/pyramid-format.md, "Region
// builds"), on a plane or on the globe, so that peak memory is one shard's whatever the
// source's size (a raster too wide for a band across it, a planet), and so that the shards
// can be built by many processes on many machines (tools/cluster).
//
// The build is a map over the finest level's shards, then a reduction up the levels: a
// finest shard is built from the source around it, a coarser one from the shards beneath it
// (their even samples and bounds). Each task writes its shard and a "carry" (what the coarser
// level and the merge need) into the staging folder "<output>.parts", each to a temporary
// name renamed into place, so a task that is run again, or twice at once, writes the same
// bytes and leaves nothing half-written. The merge checks that every planned shard was built,
// and built from every planned shard beneath it, writes the manifest once every shard is in
// place, and moves the folder to the output in one rename.
//
// On a plane the files are identical to the whole build's (buildPyramid), byte for byte (the
// manifest's build.seconds aside): a coarser shard is made from the finer shards' even
// samples and nested error bounds (Yusov & Shevtsov 2011, §4), never from the source.
//
// On the globe (one geographic source) a finest shard is built from the source's samples
// around it, read block by block, as the whole build (GlobePyramidBuilder.h) builds it: the
// same patches, the same heights to the bit, Err(P) measured at every source sample in the
// patch. A coarser shard's patch samples are its children's even samples (the same
// directions, so the same heights as the whole build's; its apron and any part no child
// covers are resampled from the source). Its Err(P) is measured at the source's samples too
// on the two levels above the finest (PyramidBuildOptions::globeMeasuredLevels) and on every
// level of a shard whose surroundings hold at most 2^24 samples: a small source's region
// build is its whole build, byte for byte. Above them it is the nested bound of Yusov &
// Shevtsov 2011, §4, signed and per quad (GlobeShardTiling.cpp), looser than the measured one
// (docs/globe.md, "Region builds"); the heights, the patches and the shards present are the
// same.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/build/PyramidBuilder.h"
#include "terrain/pyramid/PyramidLayout.h"
#include "terrain/source/DemReader.h"

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace terrain::io {

/// "<output>.parts": where the shards of a region build of `output` are gathered.
std::filesystem::path shardStagingFolder(const std::filesystem::path& output);

/// Whether `readers` can be built shard by shard on `surface`: one source (a mosaic is one
/// on a plane), not rotated; on the globe not projected either. The Error says why not,
/// naming the source.
Status shardable(PyramidSurface surface, std::span<DemReader* const> readers);

struct ShardPlan {
    PyramidSurface surface = PyramidSurface::Plane;
    PyramidLayout layout;
    /// The globe's finest face level (layout level faceFinestLevel + 1); −1 on a plane.
    int faceFinestLevel = -1;
    std::filesystem::path staging;
    /// The source and the options that decide the shards' bytes; every task and the merge
    /// check theirs against it, so shards of different builds never mix.
    std::string fingerprint;
    /// The shards to build, per layout level, row-major: on a plane every shard; on the globe
    /// those of the finest level whose surroundings reach the source, every shard above one of
    /// them, and the faces' own (none above the faces).
    std::vector<std::vector<ShardId>> shards;
    /// Bytes a shard task needs at most, about; a task refuses a budget below it.
    std::uint64_t taskBytes = 0;
};

/// Checks the source (one source, not rotated; on the globe, geographic) and options, creates
/// the staging folder with its plan, or checks that an existing one was started with the same
/// source and options. Idempotent.
Result<ShardPlan> planPyramidShards(PyramidSurface surface, DemReader& reader,
                                    const std::filesystem::path& output,
                                    const PyramidBuildOptions& options);

/// The planned shards of `shard.level + 1` that `shard` is built from: on a plane x and y in
/// [2s − 1, 2s + 2], where they exist (its children and the neighbours its apron reaches); on
/// the globe its planned children.
std::vector<ShardId> shardInputs(const ShardPlan& plan, const ShardId& shard);

struct ShardBuildSummary {
    ShardId shard;
    std::int64_t patches = 0;
    std::uint64_t bytes = 0;  ///< the shard file (none on the globe where it holds no patch)
    double seconds = 0.0;
};

/// Builds one shard of the plan's pyramid into the staging folder. A shard below the finest
/// level needs its shardInputs built first (on a plane an Error names the one missing; on the
/// globe the merge refuses it). Running it again rewrites the same bytes. Memory: one
/// shard's (ShardPlan::taskBytes), whatever the source's size.
Result<ShardBuildSummary> buildPyramidShard(PyramidSurface surface, DemReader& reader,
                                            const std::filesystem::path& output,
                                            const ShardId& shard,
                                            const PyramidBuildOptions& options);

/// Once every planned shard is built: checks them (present, of this plan, built from every
/// planned shard beneath), writes the manifest and moves the staging folder to `output` (an
/// existing one only with options.overwrite). Refuses, naming the first missing, foreign or
/// stale shard, and writes nothing, when the build is incomplete or mixed.
Result<PyramidBuildSummary> mergePyramidShards(PyramidSurface surface, DemReader& reader,
                                               const std::filesystem::path& output,
                                               const PyramidBuildOptions& options);

/// The whole pyramid as a region build in this process, one shard after another: the
/// one-worker case of a distributed build, and what buildPyramid does where the whole build
/// exceeds the memory budget (BuildWay). A failed build removes its staging folder.
Result<PyramidBuildSummary> buildPyramidByShards(PyramidSurface surface, DemReader& reader,
                                                 const std::filesystem::path& output,
                                                 const PyramidBuildOptions& options);

}  // namespace terrain::io
