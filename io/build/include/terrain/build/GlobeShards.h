// GlobeShards: a globe pyramid built one shard at a time (docs/pyramid-format.md, "Region
// builds"), so that peak memory is one shard's whatever the source's size (a planet), and so
// that the shards can be built by many processes on many machines (tools/cluster): the globe's
// counterpart of PyramidShards.h, for one geographic source.
//
// A shard of the finest face level is built from the source's samples around it, read block
// by block (GeographicBlocks), as the whole build (GlobePyramidBuilder.h) builds it: the same
// patches, the same heights to the bit, Err(P) measured at every source sample in the patch.
// A coarser shard is built from the shards beneath it: a patch's samples are its children's
// even samples (the same directions, so the same heights as the whole build's; its apron and
// any part no child covers are resampled from the source). Its Err(P) is measured at the
// source's samples too, as the whole build's, on the two levels above the finest
// (PyramidBuildOptions::globeMeasuredLevels) and on every level of a shard whose
// surroundings hold at most 2^24 samples: a small source's region build is its whole build,
// byte for byte. Above them it is the nested bound of Yusov & Shevtsov 2011, §4, signed and
// per quad: for each quad, the interval of the child's surface minus the samples in it, plus
// that of the parent's surface minus the child's, whose extremes on a quad lie at its corners
// and centre (GlobeShards.cpp, carryToParents). That bound is looser than the measured one
// (docs/globe.md, "Region builds"); the heights, the patches and the shards present are the
// same.
//
// Each task writes its shard and a carry (GlobeShardCarry.h) into "<output>.parts", each to a
// temporary name renamed into place, so a task run again, or twice at once, writes the same
// bytes. The merge checks that every planned shard was built, and built from every planned
// shard beneath it, writes the manifest and moves the folder to the output in one rename.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/source/DemReader.h"
#include "terrain/build/PyramidBuilder.h"
#include "terrain/pyramid/PyramidLayout.h"
#include "terrain/build/PyramidShards.h"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace terrain::io {

struct GlobeShardPlan {
    PyramidLayout layout;
    int faceFinestLevel = 0;
    std::filesystem::path staging;
    /// The source and the options that decide the shards' bytes (PyramidShards.h).
    std::string fingerprint;
    /// The shards to build, per layout level (none above the faces), row-major: those of the
    /// finest level whose surroundings reach the source, every shard above one of them, and
    /// the faces' own.
    std::vector<std::vector<ShardId>> shards;
};

/// Checks the source (one geographic DEM; a projected or rotated one, or several, are built
/// whole) and options, creates the staging folder with its plan, or checks that an existing
/// one was started with the same source and options. Idempotent.
Result<GlobeShardPlan> planGlobeShards(DemReader& reader, const std::filesystem::path& output,
                                       const PyramidBuildOptions& options);

/// The planned shards of level + 1 a planned shard is built from: its children.
std::vector<ShardId> globeShardInputs(const GlobeShardPlan& plan, const ShardId& shard);

/// Builds one shard of the plan's pyramid into the staging folder; below the finest level
/// from the carries of the shards beneath it (run those first: the merge refuses a shard built
/// without one of them). Memory: one shard's patches and a cache of source blocks within
/// options.memoryBudgetBytes.
Result<ShardBuildSummary> buildGlobeShard(DemReader& reader, const std::filesystem::path& output,
                                          const ShardId& shard, const PyramidBuildOptions& options);

/// Bytes a globe shard task needs besides its block cache, about; a task refuses a budget
/// below twice it.
std::uint64_t globeShardBytes(const PyramidLayout& layout);

/// Once every planned shard is built: checks them, writes the manifest and moves the staging
/// folder to `output`. Refuses, naming the first missing, foreign or stale shard, and writes
/// nothing, when the build is incomplete or mixed.
Result<PyramidBuildSummary> mergeGlobeShards(DemReader& reader, const std::filesystem::path& output,
                                             const PyramidBuildOptions& options);

/// The whole globe pyramid as a region build in this process, one shard after another: the
/// one-worker case of a distributed build, and how buildGlobePyramid builds one geographic
/// source too large for the memory budget. A failed build removes its staging folder.
Result<PyramidBuildSummary> buildGlobePyramidByShards(DemReader& reader,
                                                      const std::filesystem::path& output,
                                                      const PyramidBuildOptions& options);

}  // namespace terrain::io
