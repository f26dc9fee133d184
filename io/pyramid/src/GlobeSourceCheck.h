// The globe pyramid's half of checkErrorBoundsAgainstSource (PyramidSourceCheck.h), which
// calls it for a version-3 manifest.
#pragma once

#include "terrain/io/PyramidSourceCheck.h"

namespace terrain::io {

Result<SourceCheckReport> checkGlobeErrorBoundsAgainstSource(
    PyramidReader& reader, DemReader& source, const std::function<void(double fraction)>& progress);

}  // namespace terrain::io
