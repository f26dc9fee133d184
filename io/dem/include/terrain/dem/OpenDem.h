// openDem: the reader for the inputs a user names (files, folders, patterns, GDAL dataset
// names, mosaics, and the built-in procedural sources), and the command line's overrides.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/source/DemReader.h"

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace terrain::io {

/// The most one block a reader decodes at once may take, unless DemOpenOptions lowers it.
/// Decoders allocate a block before they read it, so a damaged header that claims more would
/// make them allocate it (8 GB for a 232-byte EXR claiming 8.4M columns, found by
/// fuzz-dem-exr; 5.1 GB for a 300-byte file GDAL took for an NGS geoid grid, found by
/// fuzz-dem-asc). A 1.3M-sample-wide float32 planet's row is 5 MB, a 256-row block of it
/// 1.3 GB.
inline constexpr std::uint64_t kDefaultMaxDecodeBytes = std::uint64_t{2} << 30U;

/// What the command line may say about the inputs; each set field overrides the file.
struct DemOpenOptions {
    std::optional<double> verticalScale;
    std::optional<double> verticalOffset;
    std::optional<double> pixelSize;  ///< map units per sample, both axes
    std::optional<double> originX;    ///< map x of the west edge of column 0
    std::optional<double> originY;    ///< map y of the north edge of row 0
    std::optional<int> epsg;          ///< sets crsKind and wkt from PROJ; unknown codes are Errors
    std::optional<double> noDataValue;  ///< raw value; samples equal to it read as NaN
    /// The raster band to read, 1-based (GDAL's -b); unset: band 1, with a warning when the
    /// input has several.
    std::optional<int> band;
    /// For globe pyramids: a projected source (UTM, Lambert, …), or a rotated geographic one,
    /// is resampled by GDAL's warper (bilinear) onto a longitude/latitude grid on WGS84 that
    /// holds every sample of it, at its finest spacing (DemInfo::resampledFrom). Geographic
    /// north-up sources and sources without a CRS open as they are.
    bool geographicGrid = false;
    /// A header whose block (a group of rows, a row of tiles, a GDAL block) decodes to more
    /// is an Error naming the file, before anything is allocated. Programs keep the default;
    /// the DEM fuzz targets lower it, since an input just under 2 GiB costs seconds a run
    /// under AddressSanitizer and a corpus of them leaves the fuzzer a few runs a second.
    std::uint64_t maxDecodeBytes = kDefaultMaxDecodeBytes;
};

/// Whether `input` is a GDAL dataset name rather than a file: a subdataset
/// (`NETCDF:"file.nc":var`, `HDF5:…`, `GTIFF_DIR:…`), a virtual file system path
/// (`/vsizip/…`, `/vsicurl/…`) or a VRT document given inline (`<VRTDataset …`).
bool isGdalDatasetName(const std::string& input);

/// Opens one input, or several as a mosaic (same CRS and pixel size, aligned grids). A
/// folder stands for the DEM files in it (by extension: .hgt, .tif, .nc, …) and a pattern
/// such as "tiles/N4*.hgt" for the files it matches, both sorted, so thousands of tiles
/// need not pass through a command line.
/// An input "procedural:size=16385,seed=7,spacing=10" (keys optional; also width=,
/// height=) is the built-in procedural terrain. GDAL dataset names (isGdalDatasetName) go
/// to GDAL. Otherwise the reader is chosen by extension: .hgt → SRTM reader;
/// .tif/.tiff/.png/.exr/.jpg/.jpeg → OpenImageIO (GeoTIFF tags through libtiff), or GDAL
/// for a band chosen with options.band, several channels, or a GeoTIFF ModelTransformation;
/// anything else and every mosaic → GDAL. A rotated or sheared grid is resampled onto a
/// north-up grid by GDAL's warper (bilinear; DemInfo::resampledFrom). Errors start with the
/// input's path: missing, empty, truncated or corrupt files, unsupported sample types,
/// rotated mosaic inputs, mosaic inputs that do not match the first. Calling thread.
Result<std::unique_ptr<DemReader>> openDem(const std::vector<std::string>& inputs,
                                           const DemOpenOptions& options = {});

}  // namespace terrain::io
