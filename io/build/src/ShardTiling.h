// ShardTiling: the seam between a region build's engine (RegionBuild.cpp: the plan's staging
// folder, the tasks' carries, the merge's checks and totals, the one-process build) and the
// surface it tiles: the plane's shards (PlanarShardTiling.cpp, built from source windows and
// from the even samples and bounds of the shards beneath) and the globe's
// (GlobeShardTiling.cpp, built from the source's samples around them and, above the measured
// levels, the nested bound). A tiling says which shards there are, what each is built from,
// builds one, and makes the merged pyramid's manifest.
#pragma once

#include "BuildFinish.h"
#include "DemStatistics.h"
#include "RegionCarry.h"
#include "terrain/base/Result.h"
#include "terrain/build/PyramidShards.h"
#include "terrain/pyramid/PyramidManifest.h"

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace terrain::io::detail {

/// What the merge adds up from the shards' carries.
struct RegionTotals {
    std::vector<double> levelMaxError;                 // per level, the largest Err(P)
    std::vector<std::int64_t> presentPatches;          // per level
    std::vector<std::vector<ShardId>> presentShards;   // per level, row-major
    DemStatistics statistics;                          // of the finest shards' source samples
    std::optional<ManifestQuantization> quantization;  // a lossy build's
    BuildTotals build;
};

class ShardTiling {
public:
    virtual ~ShardTiling() = default;

    /// The plan: layout, staging folder, fingerprint, task bytes and, where listed, shards.
    const ShardPlan& plan() const { return m_plan; }
    /// One task's work, for the memory budget's message ("a shard of 4 × 4 patches").
    virtual std::string taskName() const = 0;
    /// Refuses a shard that is not one of the plan's, naming `output`.
    virtual Status checkShard(const ShardId& shard, const std::filesystem::path& output) const = 0;
    /// Builds `shard`'s file into the staging folder and returns its carry (the engine adds
    /// the fingerprint and the time, and writes it).
    virtual Result<RegionCarry> buildShard(const ShardId& shard) = 0;
    /// Builds what the merged pyramid holds beside its shards into `folder` (the staging
    /// folder), before its manifest: a globe's native grid with --native-leaves; on a plane,
    /// nothing.
    virtual Status buildBeside(const std::filesystem::path& folder) {
        (void)folder;
        return {};
    }
    /// The merged pyramid's manifest from the shards' totals (its build fields aside);
    /// refuses a source without a valid sample, warns of one mostly of no-data.
    virtual Result<PyramidManifest> manifest(const RegionTotals& totals,
                                             std::vector<std::string>& warnings) = 0;

protected:
    ShardPlan m_plan;
};

/// The plane's tiling of `reader`: every shard of every level planned.
Result<std::unique_ptr<ShardTiling>> planarShardTiling(DemReader& reader,
                                                       const std::filesystem::path& output,
                                                       const PyramidBuildOptions& options);

/// The globe's tiling of the geographic `reader`; the shards listed only with `listShards`
/// (a planet's finest level has millions: a task does not need them).
Result<std::unique_ptr<ShardTiling>> globeShardTiling(DemReader& reader,
                                                      const std::filesystem::path& output,
                                                      const PyramidBuildOptions& options,
                                                      bool listShards);

}  // namespace terrain::io::detail
