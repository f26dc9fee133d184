#include "RegionStaging.h"

#include "RegionCarry.h"

#include <fstream>
#include <sstream>
#include <system_error>

namespace terrain::io::detail {

namespace fs = std::filesystem;

std::string regionFingerprint(const DemInfo& dem, const PyramidLayout& layout,
                              const PyramidBuildOptions& options, const nlohmann::json& extra) {
    nlohmann::json j{
        {"inputs", dem.inputs},
        {"reader", dem.readerName},
        {"width", dem.width},
        {"height", dem.height},
        {"sampleType", dem.sampleType},
        {"band", dem.band},
        {"vertical", {dem.vertical.scale, dem.vertical.offset}},
        {"noDataValue", dem.noDataValue ? nlohmann::json(*dem.noDataValue) : nlohmann::json()},
        {"flipped", {dem.rowsFlipped, dem.columnsFlipped}},
        {"patchSamples", layout.patchSamples()},
        {"blockQuads", layout.blockQuads()},
        {"shardPatches", layout.shardPatches()},
        {"compressionLevel", options.compressionLevel},
        {"maxErrorM", options.maxErrorM},
    };
    j.update(extra);
    return j.dump();
}

Status openStagingPlan(const fs::path& staging, const std::string& fingerprint, bool create) {
    const fs::path planPath = staging / "plan.json";
    std::ifstream in(planPath);
    if (in) {
        std::stringstream existing;
        existing << in.rdbuf();
        if (existing.str() != fingerprint + "\n")
            return Error{staging.string() +
                         ": a region build of another source or with other options is under way "
                         "there (remove the folder, or build with the same source and options)"};
        return {};
    }
    if (!create)
        return Error{staging.string() +
                     ": no region build there (plan it, then build its shards, before merging)"};
    return writeFileAtomically(planPath, fingerprint + "\n");
}

Status checkCarryOrigin(const fs::path& path, const std::string& planFingerprint,
                        const std::string& carryFingerprint, const ShardId& shard,
                        const ShardId& carried) {
    if (carryFingerprint != planFingerprint)
        return Error{path.string() +
                     ": built for another source or other options than this "
                     "build's plan (remove the staging folder and start again)"};
    if (!(carried == shard)) return Error{path.string() + ": holds another shard's carry"};
    return {};
}

void removeStagingFiles(const fs::path& staging) {
    std::error_code ec;
    fs::remove_all(staging / "tmp", ec);
    fs::remove(staging / "plan.json", ec);
}

StagingCleanup::~StagingCleanup() {
    std::error_code ignored;
    if (!m_staging.empty()) fs::remove_all(m_staging, ignored);
}

}  // namespace terrain::io::detail
