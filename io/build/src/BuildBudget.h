// BuildBudget: the memory budget of a build (PyramidBuildOptions::memoryBudgetBytes,
// terrain-build --memory) and the one place that decides how a pyramid is built: whole,
// where what a whole build holds fits the budget, or shard by shard (PyramidShards.h), where
// it does not and the source can be (docs/pyramid-format.md, "Region builds").
#pragma once

#include "terrain/base/Result.h"
#include "terrain/build/PyramidBuilder.h"
#include "terrain/pyramid/PyramidLayout.h"
#include "terrain/source/DemReader.h"

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace terrain::io::detail {

/// The one message of a build over its budget: "PATH: WHAT needs about N MiB, more than
/// --memory (B MiB); REMEDY", N rounded up.
std::string memoryBudgetMessage(std::string_view path, std::string_view what,
                                std::uint64_t neededBytes, std::uint64_t budgetBytes,
                                std::string_view remedy);

/// Refuses, with memoryBudgetMessage, `neededBytes` over `budgetBytes`.
Status checkMemoryBudget(std::string_view path, std::string_view what, std::uint64_t neededBytes,
                         std::uint64_t budgetBytes, std::string_view remedy);

/// Peak memory of a planar pass whose bands are `bandPatches` patches wide, about: the whole
/// build's bands are the finest level's width, a shard task's its shard's.
std::uint64_t planarBandBytes(const PyramidLayout& layout, std::int64_t bandPatches);

/// How the build runs: BuildWay::Whole or BuildWay::ByShards, and, when the budget made it
/// shard by shard, a warning saying so.
struct BuildDecision {
    BuildWay way = BuildWay::Whole;
    std::optional<std::string> warning;
};

/// Decides `requested` (BuildWay::Automatic: whole where its largest structure fits the
/// budget, by shards where not and the sources are shardable, refused otherwise).
Result<BuildDecision> decideBuildWay(PyramidSurface surface, std::span<DemReader* const> readers,
                                     const std::filesystem::path& output,
                                     const PyramidBuildOptions& options, BuildWay requested);

}  // namespace terrain::io::detail
