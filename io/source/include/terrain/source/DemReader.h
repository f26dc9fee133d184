// DemReader: one interface over every DEM a user brings (GeoTIFF/PNG/EXR through
// OpenImageIO, SRTM .hgt, anything GDAL knows, mosaics of several files: terrain::dem's
// openDem; the procedural sources: ProceduralDems.h), read window by window so no raster is
// ever held whole. The builders read through it alone, so they link no file library.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/source/Georeference.h"
#include "terrain/source/VerticalTransform.h"

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace terrain::io {

/// A source resampled by GDAL's warper: a rotated or sheared one onto a north-up grid in its
/// own CRS, or (DemOpenOptions::geographicGrid) a projected one onto a longitude/latitude grid
/// on WGS84. Where its own samples lie on that grid, so error bounds are made and checked
/// against them.
struct ResampledGrid {
    std::int64_t width = 0;  ///< the source's own columns and rows
    std::int64_t height = 0;
    std::array<double, 6> geoTransform{};  ///< the source's, in GDAL's order
    /// Source sample (column c, row r) lies at x = toGrid[0] + toGrid[1]·c + toGrid[2]·r,
    /// y = toGrid[3] + toGrid[4]·c + toGrid[5]·r on the resampled grid, in its samples
    /// (column 0 at x = 0, row 0 at y = 0); every sample lies inside that grid.
    /// Zero when `fromCrs` is set: a reprojection places no sample affinely.
    std::array<double, 6> toGrid{};
    std::string method = "bilinear";  ///< GDAL's resampling
    /// The source's own CRS (WKT) when it was reprojected onto a geographic grid; empty
    /// when only rotated or sheared within its CRS.
    std::string fromCrs{};
};

struct DemInfo {
    std::string path;                 ///< the input (first input of a mosaic), for messages
    std::string readerName;           ///< "oiio", "gdal", "hgt", "procedural"
    std::vector<std::string> inputs;  ///< every input file (or the procedural spec)
    std::int64_t width = 0;           ///< columns (x, east)
    std::int64_t height = 0;          ///< rows (y, south); row 0 is the north edge
    /// Source sample type: "uint8", "int8", "uint16", "int16", "uint32", "int32",
    /// "float16", "float32", "float64" (GDAL also "int64", "uint64").
    std::string sampleType;
    bool hasGeoreference = false;  ///< from the file or the options
    /// Without one: crsKind Unknown, origin 0, pixel size 1 (map units are samples).
    Georeference georeference;
    VerticalTransform vertical;
    /// Raw value the source declares as no-data (GeoTIFF GDAL_NODATA, netCDF _FillValue,
    /// SRTM voids −32768), compared before the vertical transform.
    std::optional<double> noDataValue;  ///< raw value; samples equal to it read as NaN
    /// What the reader had to assume, for the user to see (a spacing without a CRS taken
    /// as metres, no spacing at all taken as 1 m), each naming the file and the flags that
    /// say otherwise.
    std::vector<std::string> warnings;
    /// Which raster band (1-based, GDAL's numbering) of how many the heights come from.
    int band = 1;
    int bandCount = 1;
    /// The source's rows run south to north, or its columns east to west: read flipped,
    /// so row 0 is still the north edge and column 0 the west edge.
    bool rowsFlipped = false;
    bool columnsFlipped = false;
    /// Set when the source is rotated or sheared, or reprojected (geographicGrid): this grid
    /// is its bilinear resampling and DemReader::originalSamples reads the source's own
    /// samples, which DemReader::placeOriginalSamples places on it.
    std::optional<ResampledGrid> resampledFrom;
};

class DemReader {
public:
    virtual ~DemReader() = default;
    virtual const DemInfo& info() const = 0;

    /// Reads columns [x0, x0 + width) of rows [y0, y0 + rows) into `out` (row-major,
    /// width · rows floats) as metres: the vertical transform applied, no-data and NaN
    /// samples as quiet NaN. The window must lie inside the raster. A broken or
    /// truncated file is an Error naming the file and what is wrong. One thread at a time.
    virtual Status readWindow(std::int64_t x0, std::int64_t y0, std::int64_t width,
                              std::int64_t rows, std::span<float> out) = 0;

    /// For a resampled source (info().resampledFrom): a reader of the source's own
    /// samples, on its own grid (rows and columns as stored, no georeference), which
    /// info().resampledFrom places on this grid. Null for every other source. Same thread
    /// rules; owned by this reader.
    virtual DemReader* originalSamples() { return nullptr; }

    /// For a resampled source: where own samples (firstColumn + i, row), i < x.size(), lie on
    /// this grid, in its samples (column 0's centre at x = 0, row 0's at y = 0); through
    /// ResampledGrid::toGrid, or the CRS transform of a reprojection. An Error for any other
    /// source, or a sample the transform cannot place. Same thread rules.
    virtual Status placeOriginalSamples(std::int64_t /*firstColumn*/, std::int64_t /*row*/,
                                        std::span<double> /*x*/, std::span<double> /*y*/) {
        return Error{info().path + ": not a resampled source; its samples are the grid's"};
    }
};

/// The DemReader::readWindow precondition (a programmer error when broken, hence an assert).
void assertDemWindow(const DemInfo& info, std::int64_t x0, std::int64_t y0, std::int64_t width,
                     std::int64_t rows, std::span<float> out);

}  // namespace terrain::io
