// RegionCarry: what a region build's shard task hands to the tasks of the coarser level and
// to the merge (docs/pyramid-format.md, "Region builds"), on either surface: its summary
// (patches, largest Err(P), a finest shard's statistics of its own source samples, the shards
// beneath it that it was built from) and what its parent is built from. A planar shard's:
// its patches' Err_Appr and shares of their parents' Err_Int and its even samples, the
// coarser level's samples it owns. A globe shard's: per patch its key, Err(P), even samples
// and, per parent quad over it, the interval of parent − source (the nested bound, Yusov &
// Shevtsov 2011, §4, signed and per quad). Temporary files of the staging folder, written to
// a temporary name and renamed, in the machine's byte order (a build's tasks run on one kind
// of machine).
#pragma once

#include "DemStatistics.h"
#include "LevelBuilder.h"
#include "terrain/base/Result.h"
#include "terrain/build/PyramidBuilder.h"
#include "terrain/pyramid/PyramidLayout.h"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace terrain::io::detail {

struct RegionCarry {
    std::string fingerprint;  // the plan's (PyramidShards.h)
    ShardId shard;
    // Summary, for the merge.
    std::int64_t patches = 0;
    float levelMaxError = 0.0f;             // largest Err(P) of the shard
    double finestLargestQuantErrorM = 0.0;  // a lossy finest shard's largest rounding
    DemStatistics statistics;               // a finest shard's own source samples
    PyramidBuildPhases phases;
    double seconds = 0.0;
    std::vector<ShardId> builtFrom;  // the shards of level + 1 whose carries it read
    // For the parent: the planar tiling's.
    ChildBounds bounds;
    std::int64_t evenX0 = 0, evenY0 = 0, evenWidth = 0, evenHeight = 0;
    // Both tilings': the even samples (planar: evenWidth × evenHeight, row-major; globe: per
    // patch (q/2 + 1)², row-major, unrounded).
    std::vector<float> evenHeights;
    std::vector<std::uint8_t> evenValid;
    // The globe tiling's: per patch (its face-level key) its Err(P), and for each of the
    // parent's quads over it ((q/2)², row-major) the interval of parent − source (low > high:
    // none; none at all where the parent is measured at the samples).
    std::vector<std::uint64_t> keys;
    std::vector<float> errors;
    std::vector<float> parentLow, parentHigh;
};

/// "tmp/carry/L<level>/<sy>/<sx>.carry" in the staging folder.
std::filesystem::path carryPath(const std::filesystem::path& staging, const ShardId& shard);

Status writeCarry(const std::filesystem::path& path, const RegionCarry& carry);

/// Reads a carry; without `whole` only its summary. Errors name the file: missing, truncated,
/// not a carry, or inconsistent.
Result<RegionCarry> readCarry(const std::filesystem::path& path, bool whole);

/// Reads the carry of `shard` of the plan `fingerprint` in `staging`, refusing another
/// plan's or another shard's.
Result<RegionCarry> readShardCarry(const std::filesystem::path& staging, const ShardId& shard,
                                   const std::string& fingerprint, bool whole);

/// Writes `bytes` to a temporary name beside `path` and renames it into place.
Status writeFileAtomically(const std::filesystem::path& path, const std::string& bytes);

}  // namespace terrain::io::detail
