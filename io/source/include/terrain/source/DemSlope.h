// How steep a DEM is as its samples and its georeference say: the check that catches a
// DEM built with the wrong horizontal spacing or height unit (raw decimetres read as
// metres, a 5 km grid read as 1 m), which draws as a forest of needles kilometres high.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/source/DemReader.h"

#include <cstdint>
#include <optional>
#include <string>

namespace terrain::io {

struct DemSlopeSample {
    /// Median of |Δh| / distance over the sampled pairs of adjacent valid samples.
    double medianSlope = 0.0;
    double metresPerColumn = 1.0;  ///< the horizontal spacing the slopes were taken with
    double metresPerRow = 1.0;
    std::uint64_t pairs = 0;  ///< adjacent valid pairs sampled (0: nothing to judge)
};

/// Slopes between adjacent samples on up to 32 pairs of rows spread over the raster (at
/// most 2048 columns of each, around the centre column), east-west and north-south.
/// Spacing in metres: the pixel size for projected CRSs (taken as metres), degrees at
/// the raster's centre latitude on a sphere of the WGS84 equatorial radius for
/// geographic ones (a warning needs no more), 1 m for no georeference.
Result<DemSlopeSample> sampleSlopes(DemReader& reader);

/// A median slope above this (about 63°) is steeper than any real terrain's: real DEMs,
/// Himalayan walls included, have median slopes well under 1.
inline constexpr double kAbsurdMedianSlope = 2.0;

/// A warning naming the file, the slope and the flags that fix the usual causes, when
/// the median slope is above kAbsurdMedianSlope; nullopt otherwise.
std::optional<std::string> absurdReliefWarning(const DemInfo& info, const DemSlopeSample& slopes);

}  // namespace terrain::io
