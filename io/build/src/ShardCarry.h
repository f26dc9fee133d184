// ShardCarry: what a region build's shard task hands to the coarser level's tasks and to
// the merge (docs/pyramid-format.md, "Region builds"): its patches' Err_Appr and shares of
// their parents' Err_Int, its even samples (the coarser level's samples it owns), the
// statistics of its DEM samples and its largest Err(P). And the DEM's filled last column
// and last row, which the finest tasks on the east and south edges keep for every coarser
// level. Temporary files of the staging folder, written to a temporary name and renamed,
// in the machine's byte order (a build's tasks run on one kind of machine).
#pragma once

#include "LevelBuilder.h"
#include "terrain/base/Result.h"
#include "terrain/pyramid/PyramidLayout.h"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace terrain::io::detail {

struct ShardCarry {
    std::string fingerprint;  // the plan's (PyramidShards.h)
    ShardId shard;
    // Summary, for the merge.
    std::int64_t patches = 0;
    float levelMaxError = 0.0f;             // largest Err(P) of the shard
    double finestLargestQuantErrorM = 0.0;  // a lossy finest shard's largest rounding
    DemStatistics statistics;               // a finest shard's own DEM samples
    PyramidBuildPhases phases;
    double seconds = 0.0;
    // For the coarser level's task.
    ChildBounds bounds;
    std::int64_t evenX0 = 0, evenY0 = 0, evenWidth = 0, evenHeight = 0;
    std::vector<float> evenHeights;  // evenWidth × evenHeight, row-major
    std::vector<std::uint8_t> evenValid;
};

/// "tmp/carry/L<level>/<sy>/<sx>.carry" in the staging folder.
std::filesystem::path carryPath(const std::filesystem::path& staging, const ShardId& shard);

Status writeCarry(const std::filesystem::path& path, const ShardCarry& carry);

/// Reads a carry; without `whole` only its fingerprint, shard and summary. Errors name the
/// file: missing, truncated or not a carry.
Result<ShardCarry> readCarry(const std::filesystem::path& path, bool whole);

/// One edge of the DEM kept by a finest shard: values at DEM rows (east) or columns (south)
/// first, first + 1, …
struct EdgeRun {
    std::int64_t first = 0;
    std::vector<float> values;
};

/// "tmp/edges/east-<sy>.f32" and "tmp/edges/south-<sx>.f32" in the staging folder.
std::filesystem::path edgePath(const std::filesystem::path& staging, bool east, std::int64_t index);
Status writeEdge(const std::filesystem::path& path, const EdgeRun& run);
Result<EdgeRun> readEdge(const std::filesystem::path& path);

/// Writes `bytes` to a temporary name beside `path` and renames it into place.
Status writeFileAtomically(const std::filesystem::path& path, const std::string& bytes);

}  // namespace terrain::io::detail
