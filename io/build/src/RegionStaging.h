// RegionStaging: the staging folder "<output>.parts" of a region build, planar or globe
// (PyramidShards.h): its plan file, which keeps shards of different
// builds apart; the check of a carry's origin; what the merge removes; and the one-process
// build's cleanup.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/source/DemReader.h"
#include "terrain/build/PyramidBuilder.h"
#include "terrain/pyramid/PyramidLayout.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>

namespace terrain::io::detail {

/// What decides a region build's shards' bytes: the source as read, the layout, the options
/// and the tiling's own `extra` fields, as one line of JSON.
std::string regionFingerprint(const DemInfo& dem, const PyramidLayout& layout,
                              const PyramidBuildOptions& options, const nlohmann::json& extra);

/// Checks that the staging folder's plan is `fingerprint`'s (the source and the options that
/// decide the shards' bytes), or, with `create`, writes it there when there is none.
Status openStagingPlan(const std::filesystem::path& staging, const std::string& fingerprint,
                       bool create);

/// Refuses a carry (at `path`) of another build's plan, or of another shard than `shard`.
Status checkCarryOrigin(const std::filesystem::path& path, const std::string& planFingerprint,
                        const std::string& carryFingerprint, const ShardId& shard,
                        const ShardId& carried);

/// What the merge removes before the folder becomes the pyramid: the carries and the plan.
void removeStagingFiles(const std::filesystem::path& staging);

/// A one-process region build's own staging folder: removed unless the merge moved it into
/// place (merged()).
class StagingCleanup {
public:
    explicit StagingCleanup(std::filesystem::path staging) : m_staging(std::move(staging)) {}
    StagingCleanup(const StagingCleanup&) = delete;
    StagingCleanup& operator=(const StagingCleanup&) = delete;
    ~StagingCleanup();
    void merged() { m_staging.clear(); }

private:
    std::filesystem::path m_staging;
};

}  // namespace terrain::io::detail
