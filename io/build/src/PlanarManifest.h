// PlanarManifest: the manifest of a planar pyramid, whole or merged from shards
// (PyramidShards.h), made from what the build learned on its way, so both write the same
// manifest from the same totals.
#pragma once

#include "DemStatistics.h"
#include "terrain/base/Result.h"
#include "terrain/pyramid/PyramidLayout.h"
#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/source/DemReader.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace terrain::io::detail {

/// Whether a planar pyramid of `dem` stores the no-data mask.
bool planarMaskStored(const DemInfo& dem);

/// A resampled source's own samples (DemInfo::resampledFrom): how many are valid, and the
/// largest distance of one from the finest level's surface.
struct OriginalSamples {
    std::int64_t validSamples = 0;
    double finestDistance = 0.0;
};

/// The manifest of a planar pyramid of `reader` (its build fields aside): `statistics` of
/// the finest level's source samples, `levelMaxError` per level. Refuses a source without a
/// valid sample; warns, into `warnings`, of one mostly of no-data.
Result<PyramidManifest> planarManifest(DemReader& reader, const PyramidLayout& layout,
                                       const DemStatistics& statistics,
                                       const std::vector<double>& levelMaxError,
                                       const std::optional<ManifestQuantization>& quantization,
                                       const OriginalSamples& original,
                                       std::vector<std::string>& warnings);

}  // namespace terrain::io::detail
