// GDAL's warper as the DEM readers use it: bilinear interpolation of the four nearest
// source samples onto a grid given by its extent and size, lazily (a VRT: windows are
// warped when read), samples outside the source NaN. Shared by the rotated-grid resampling
// (GdalResampledDem.cpp) and the reprojection onto a geographic grid (GdalGeographicDem.cpp).
#pragma once

#include "GdalSession.h"
#include "terrain/base/Result.h"
#include "terrain/source/DemReader.h"

#include <cstdint>
#include <string>

namespace terrain::io::detail {

/// The grid to warp onto, in the target CRS's units (for a geographic one, degrees of
/// longitude for x and latitude for y).
struct WarpGrid {
    double west = 0.0, south = 0.0, east = 0.0, north = 0.0;
    std::int64_t width = 0, height = 0;
    std::string targetCrs;  ///< as gdalwarp's -t_srs takes it; empty: the source's own
    std::string sourceCrs;  ///< -s_srs; empty: the dataset's own
};

/// The warper's lazy output, and the one-band VRT it reads when the source has several bands
/// (declared first, so it closes after the dataset that reads it).
struct WarpedDataset {
    GdalDataset band;
    GdalDataset warped;
};

/// Band `info.band` of `source` warped onto `grid`, as Float64 when `wide` (samples a float
/// does not hold) else Float32. `what` finishes "GDAL's warper cannot resample it onto …"
/// in the Error, which names info.path.
Result<WarpedDataset> warpBilinear(GDALDataset& source, const DemInfo& info, const WarpGrid& grid,
                                   bool wide, const std::string& what);

/// Whether a band of this GDAL type needs Float64 to be read without loss.
bool isWideSampleType(GDALDataType type);

}  // namespace terrain::io::detail
