// The "seams" of the tools' JSON summaries (terrain-build --json, terrain-inspect --json,
// terrain-bench's bench.json): a globe pyramid's manifest globe.seams, each with whether the
// slope its blend adds stays within its source's 99th-percentile slope (docs/globe.md,
// "How it works"). An empty array for a pyramid without them (a plane, one source, or one
// built before the band followed the step).
#pragma once

#include "terrain/pyramid/PyramidManifest.h"

namespace terrain::tools {

/// Whether a seam stays within its source's slopes (the target: seam slope ≤ the
/// 99th-percentile slope).
inline bool seamWithinSourceSlopes(const io::ManifestSeam& seam) {
    return seam.seamSlope <= seam.sourceSlopeP99;
}

template <typename Json>
Json seamsJson(const io::PyramidManifest& manifest) {
    Json seams = Json::array();
    if (!manifest.globe) return seams;
    for (const io::ManifestSeam& s : manifest.globe->seams)
        seams.push_back({{"input", s.input},
                         {"seamSlope", s.seamSlope},
                         {"sourceSlopeP99", s.sourceSlopeP99},
                         {"withinSourceSlopes", seamWithinSourceSlopes(s)},
                         {"bandScaleRatio", s.bandScaleRatio},
                         {"largestStepM", s.largestStepM},
                         {"bandPixels", {s.bandPixels[0], s.bandPixels[1]}},
                         {"bandMetres", {s.bandMetres[0], s.bandMetres[1]}},
                         {"cappedPixels", s.cappedPixels}});
    return seams;
}

}  // namespace terrain::tools
