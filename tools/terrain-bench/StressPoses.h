// StressPoses: the stability suite's cases found in the user's own pyramid, so that
// `terrain-bench --stability` shows where each LOD method breaks on that data: its steepest
// slope seen from the foot (the cliff), its sharpest peak (the spike), a walker's grazing
// view 1 m above the ground towards its highest point, the whole terrain from afar, and the
// edge of its no-data.
// AccuracyStabilityTest flies the synthetic versions (a 1,000 m cliff, spikes, a needle
// forest); these are located by scanning one level of the pyramid (the finest with at most
// 2049 samples a side) and placed on the full-resolution surface. Planar pyramids only.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/runtime/Camera.h"

#include <filesystem>
#include <string>
#include <vector>

namespace terrain::tools {

struct StressPose {
    std::string name;  ///< a short key: "cliff", "peak", "grazing", "whole-terrain", "no-data-edge"
    std::string what;  ///< where it looks, in words, with the place in DEM samples
    runtime::Camera camera;
};

/// The poses for `pyramid` with a viewport of widthPx × heightPx; "no-data-edge" only when
/// the DEM has no-data samples. Errors name the pyramid.
Result<std::vector<StressPose>> findStressPoses(const std::filesystem::path& pyramid, int widthPx,
                                                int heightPx);

}  // namespace terrain::tools
