// GlobeTestSources: what the globe pyramid tests build from: a smooth terrain of latitude and
// longitude (hundreds of metres of relief at several wavelengths) for GeographicFunctionDem,
// and small patches and shards, so that a few hundred samples already make several levels
// and shards.
#pragma once

#include "terrain/build/PyramidBuilder.h"

#include <cmath>

namespace terrain::test {

inline float hills(double latitude, double longitude) {
    return static_cast<float>(800.0 + 600.0 * std::sin(latitude * 7.0) * std::cos(longitude * 5.0) +
                              150.0 * std::sin(longitude * 31.0 + latitude * 17.0));
}

inline io::PyramidBuildOptions smallGlobePatches() {
    io::PyramidBuildOptions options;
    options.patchSamples = 17;
    options.blockQuads = 4;
    options.shardPatches = 4;
    options.threads = 2;
    options.compressionLevel = 1;
    return options;
}

}  // namespace terrain::test
