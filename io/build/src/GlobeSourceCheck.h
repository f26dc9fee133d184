// The globe pyramid's half of the source check (PyramidSourceCheck.h).
#pragma once

#include "terrain/build/PyramidSourceCheck.h"

namespace terrain::io {

Result<SourceCheckReport> checkGlobeErrorBoundsAgainstSources(
    PyramidReader& reader, std::span<DemReader* const> sources,
    const std::function<void(double fraction)>& progress);

}  // namespace terrain::io
