// PlanarBuildTotals: what a planar build learns on its way that the manifest records, and
// the steps that end every planar build, whole or merged from shards (PyramidShards.h), so
// both write the same manifest from the same totals.
#pragma once

#include "LevelBuilder.h"
#include "terrain/build/PyramidBuilder.h"

#include <filesystem>
#include <optional>
#include <vector>

namespace terrain::io::detail {

struct PlanarBuildTotals {
    DemStatistics statistics;          // of the finest level's DEM samples
    std::vector<float> levelMaxError;  // per level, the largest Err(P)
    std::int64_t patches = 0;
    std::int64_t originalValidSamples = 0;  // a resampled source's
    double originalFinestDistance = 0.0;
    std::optional<ManifestQuantization> quantization;  // a lossy build's
    PyramidBuildPhases phases;
    double seconds = 0.0;
};

/// Whether a planar pyramid of `dem` stores the no-data mask.
bool planarMaskStored(const DemInfo& dem);

/// Peak memory of a pass whose bands are `bandPatches` patches wide, about.
std::uint64_t planarBandBytes(const PyramidLayout& layout, std::int64_t bandPatches);

/// Writes the manifest of a finished planar build into `folder` (every shard in place) and
/// returns the summary; refuses a source without a valid sample.
Result<PyramidBuildSummary> finishPlanarBuild(DemReader& reader, const PyramidLayout& layout,
                                              const PlanarBuildTotals& totals,
                                              const std::filesystem::path& folder);

}  // namespace terrain::io::detail
