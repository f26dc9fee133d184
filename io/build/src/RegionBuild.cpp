// The region build's engine (PyramidShards.h), the same on both surfaces: the plan and its
// staging folder, a task's carry, the merge's checks and totals, and the one-process build;
// what differs between the plane and the globe is the ShardTiling (ShardTiling.h).
#include "terrain/build/PyramidShards.h"

#include "BuildBudget.h"
#include "BuildClock.h"
#include "BuildFinish.h"
#include "BuildOutput.h"
#include "RegionCarry.h"
#include "RegionStaging.h"
#include "ShardTiling.h"

#include <fmt/core.h>

#include <algorithm>
#include <system_error>

namespace terrain::io {
namespace {

namespace fs = std::filesystem;

// Checks the source and the options, makes the surface's tiling and opens (with `create`,
// makes) the staging folder's plan.
Result<std::unique_ptr<detail::ShardTiling>> openPlan(PyramidSurface surface, DemReader& reader,
                                                      const fs::path& output,
                                                      const PyramidBuildOptions& options,
                                                      bool create, bool listShards) {
    if (Status delta = checkMaxErrorM(output, options.maxErrorM); !delta) return delta.error();
    DemReader* const readers[] = {&reader};
    if (Status canShard = shardable(surface, readers); !canShard) return canShard.error();
    auto tiling = surface == PyramidSurface::Globe
                      ? detail::globeShardTiling(reader, output, options, listShards)
                      : detail::planarShardTiling(reader, output, options);
    if (!tiling) return tiling.error();
    const ShardPlan& plan = tiling.value()->plan();
    if (Status fits = detail::checkMemoryBudget(reader.info().path, tiling.value()->taskName(),
                                                plan.taskBytes, options.memoryBudgetBytes,
                                                "lower --shard-patches or raise --memory");
        !fits)
        return fits.error();
    if (Status opened = detail::openStagingPlan(plan.staging, plan.fingerprint, create); !opened)
        return opened.error();
    return tiling;
}

std::string shardName(const ShardId& s) { return fmt::format("{}/{}/{}", s.level, s.x, s.y); }

}  // namespace

fs::path shardStagingFolder(const fs::path& output) {
    fs::path normal = output.lexically_normal();
    if (normal.filename().empty()) normal = normal.parent_path();
    return normal.string() + ".parts";
}

Result<ShardPlan> planPyramidShards(PyramidSurface surface, DemReader& reader,
                                    const fs::path& output, const PyramidBuildOptions& options) {
    auto opened = openPlan(surface, reader, output, options, true, true);
    if (!opened) return opened.error();
    return opened.value()->plan();
}

std::vector<ShardId> shardInputs(const ShardPlan& plan, const ShardId& shard) {
    std::vector<ShardId> inputs;
    const PyramidLayout& layout = plan.layout;
    if (shard.level >= layout.finestLevel()) return inputs;
    const int finer = shard.level + 1;
    const std::vector<ShardId>& planned = plan.shards[static_cast<std::size_t>(finer)];
    // On a plane a patch's apron reaches the shards beside its children; on the globe a
    // patch is made from its children alone.
    const std::int64_t reach = plan.surface == PyramidSurface::Plane ? 1 : 0;
    for (std::int64_t y = std::max<std::int64_t>(0, 2 * shard.y - reach);
         y <= std::min(2 * shard.y + 1 + reach, layout.shardsY(finer) - 1); ++y)
        for (std::int64_t x = std::max<std::int64_t>(0, 2 * shard.x - reach);
             x <= std::min(2 * shard.x + 1 + reach, layout.shardsX(finer) - 1); ++x) {
            const ShardId input{finer, x, y};
            if (std::binary_search(planned.begin(), planned.end(), input,
                                   [](const ShardId& a, const ShardId& b) {
                                       return std::pair(a.y, a.x) < std::pair(b.y, b.x);
                                   }))
                inputs.push_back(input);
        }
    return inputs;
}

Result<ShardBuildSummary> buildPyramidShard(PyramidSurface surface, DemReader& reader,
                                            const fs::path& output, const ShardId& shard,
                                            const PyramidBuildOptions& options) {
    const auto start = BuildClock::now();
    auto opened = openPlan(surface, reader, output, options, true, false);
    if (!opened) return opened.error();
    detail::ShardTiling& tiling = *opened.value();
    const ShardPlan& plan = tiling.plan();
    if (Status planned = tiling.checkShard(shard, output); !planned) return planned.error();
    auto built = tiling.buildShard(shard);
    if (!built) return built.error();
    detail::RegionCarry& carry = built.value();
    carry.fingerprint = plan.fingerprint;
    carry.shard = shard;
    carry.seconds = secondsSince(start);
    if (Status written = detail::writeCarry(detail::carryPath(plan.staging, shard), carry);
        !written)
        return written.error();
    ShardBuildSummary summary;
    summary.shard = shard;
    summary.patches = carry.patches;
    std::error_code ec;
    const fs::path file = plan.staging / plan.layout.shardPath(shard);
    summary.bytes = fs::exists(file, ec) ? fs::file_size(file, ec) : 0;
    summary.seconds = carry.seconds;
    return summary;
}

Result<PyramidBuildSummary> mergePyramidShards(PyramidSurface surface, DemReader& reader,
                                               const fs::path& output,
                                               const PyramidBuildOptions& options) {
    auto opened = openPlan(surface, reader, output, options, false, true);
    if (!opened) return opened.error();
    detail::ShardTiling& tiling = *opened.value();
    const ShardPlan& plan = tiling.plan();
    const PyramidLayout& layout = plan.layout;

    detail::RegionTotals totals;
    const auto levels = static_cast<std::size_t>(layout.levelCount());
    totals.levelMaxError.assign(levels, 0.0);
    totals.presentPatches.assign(levels, 0);
    totals.presentShards.resize(levels);
    if (options.maxErrorM > 0.0) totals.quantization = ManifestQuantization{options.maxErrorM};
    for (int level = layout.finestLevel(); level >= 0; --level) {
        const auto l = static_cast<std::size_t>(level);
        for (const ShardId& shard : plan.shards[l]) {
            std::error_code ec;
            const fs::path file = plan.staging / layout.shardPath(shard);
            if (!fs::exists(detail::carryPath(plan.staging, shard), ec))
                return Error{file.string() + ": missing (shard " + shardName(shard) +
                             " was not built)"};
            auto read = detail::readShardCarry(plan.staging, shard, plan.fingerprint, false);
            if (!read) return read.error();
            const detail::RegionCarry& c = read.value();
            for (const ShardId& input : shardInputs(plan, shard))
                if (std::find(c.builtFrom.begin(), c.builtFrom.end(), input) == c.builtFrom.end())
                    return Error{fmt::format(
                        "{}: shard {} was built before shard {} beneath it (build it again, "
                        "then merge)",
                        plan.staging.string(), shardName(shard), shardName(input))};
            if ((c.patches > 0) != fs::is_regular_file(file, ec))
                return Error{file.string() + (c.patches > 0 ? ": missing" : ": not of this build")};
            if (c.patches > 0) totals.presentShards[l].push_back(shard);
            totals.presentPatches[l] += c.patches;
            totals.levelMaxError[l] = std::max(totals.levelMaxError[l], double(c.levelMaxError));
            totals.build.patches += c.patches;
            totals.build.phases.readSeconds += c.phases.readSeconds;
            totals.build.phases.boundsSeconds += c.phases.boundsSeconds;
            totals.build.phases.writeSeconds += c.phases.writeSeconds;
            totals.build.seconds += c.seconds;
            if (level != layout.finestLevel()) continue;
            totals.statistics.add(c.statistics);
            if (totals.quantization)
                totals.quantization->finestLargestErrorM =
                    std::max(totals.quantization->finestLargestErrorM, c.finestLargestQuantErrorM);
        }
    }
    if (Status beside = tiling.buildBeside(plan.staging); !beside) return beside.error();
    auto manifest = tiling.manifest(totals, totals.build.warnings);
    if (!manifest) return manifest.error();
    if (manifest.value().globe) {
        manifest.value().globe->seaLevelM = options.globeSeaLevelM;
        manifest.value().globe->oversampleLevels = options.globeOversampleLevels;
    }

    auto adopted = PartialBuildFolder::adopt(output, plan.staging, options.overwrite);
    if (!adopted) return adopted.error();
    auto summary =
        detail::finishBuild(std::move(manifest).value(), std::move(totals.build), plan.staging);
    if (!summary) return summary.error();
    detail::removeStagingFiles(plan.staging);
    summary.value().bytes = folderBytes(plan.staging);
    if (Status committed = adopted.value().commit(); !committed) return committed.error();
    return summary;
}

Result<PyramidBuildSummary> buildPyramidByShards(PyramidSurface surface, DemReader& reader,
                                                 const fs::path& output,
                                                 const PyramidBuildOptions& options) {
    const auto start = BuildClock::now();
    std::error_code ec;
    if (fs::exists(output, ec) && !options.overwrite)
        return Error{output.string() + ": already exists (pass --overwrite to replace it)"};
    auto planned = planPyramidShards(surface, reader, output, options);
    if (!planned) return planned.error();
    const ShardPlan& plan = planned.value();
    detail::StagingCleanup cleanup(plan.staging);

    // Progress by patches on a plane (every shard's known), by shards on the globe.
    const PyramidLayout& layout = plan.layout;
    const bool plane = surface == PyramidSurface::Plane;
    double total = 0.0, done = 0.0;
    for (int level = 0; level < layout.levelCount(); ++level)
        total += plane ? double(layout.patchCount(level))
                       : double(plan.shards[static_cast<std::size_t>(level)].size());
    for (int level = layout.finestLevel(); level >= 0; --level)
        for (const ShardId& shard : plan.shards[static_cast<std::size_t>(level)]) {
            auto built = buildPyramidShard(surface, reader, output, shard, options);
            if (!built) return built.error();
            done += plane ? double(built.value().patches) : 1.0;
            if (options.progress) options.progress({level, std::min(1.0, done / total)});
        }
    auto merged = mergePyramidShards(surface, reader, output, options);
    if (!merged) return merged;
    cleanup.merged();
    merged.value().seconds = secondsSince(start);
    return merged;
}

}  // namespace terrain::io
