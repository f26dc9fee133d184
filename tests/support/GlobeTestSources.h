// GlobeTestSources: what the globe pyramid tests build from: smooth terrains of latitude and
// longitude (hundreds of metres of relief at several wavelengths) for GeographicFunctionDem,
// and small patches and shards, so that a few hundred samples already make several levels
// and shards.
#pragma once

#include "GeographicFunctionDem.h"
#include "terrain/build/GlobePyramidBuilder.h"
#include "terrain/build/PyramidBuilder.h"

#include <cmath>
#include <filesystem>
#include <numbers>

namespace terrain::test {

inline float hills(double latitude, double longitude) {
    return static_cast<float>(800.0 + 600.0 * std::sin(latitude * 7.0) * std::cos(longitude * 5.0) +
                              150.0 * std::sin(longitude * 31.0 + latitude * 17.0));
}

// ±1.8 km of smooth relief over the whole planet, below sea level in places; the terms that
// vary with longitude fade towards the poles, so the surface is continuous there as a real
// one is (a function of longitude alone at the pole has no one height there to measure).
inline float reliefPlanet(double latitude, double longitude) {
    constexpr double kDegree = std::numbers::pi / 180.0;
    const double phi = latitude * kDegree, lambda = longitude * kDegree;
    return static_cast<float>(std::cos(phi) *
                                  (1500.0 * std::sin(7.0 * phi) * std::cos(5.0 * lambda) +
                                   300.0 * std::sin(31.0 * lambda + 17.0 * phi)) +
                              400.0 * std::sin(3.0 * phi));
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

/// reliefPlanet on a 0.5° grid, built at `pyramid` as a globe pyramid of 33-sample patches:
/// what the globe session and accuracy tests draw.
inline Result<io::PyramidBuildSummary> buildReliefPlanet(const std::filesystem::path& pyramid) {
    GeographicFunctionDem source(-180.0, 90.0, 720, 360, 0.5, 0.5, reliefPlanet);
    io::PyramidBuildOptions options;
    options.patchSamples = 33;
    options.blockQuads = 8;
    options.shardPatches = 8;
    options.threads = 2;
    return io::buildGlobePyramid(source, pyramid, options);
}

}  // namespace terrain::test
