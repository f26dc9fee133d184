// Georeference: where a north-up raster lies on the map, as an affine pixel-to-map
// transform plus a CRS code. Written into GeoTIFFs (GeoTIFF 1.1, OGC 19-008r4, §7).
#pragma once

namespace terrain::io {

/// A north-up raster's placement (no rotation). Pixels are areas (GeoTIFF
/// RasterPixelIsArea): pixel (col, row) covers map x in [originX + col·pixelSizeX,
/// originX + (col+1)·pixelSizeX] and map y in [originY − (row+1)·pixelSizeY,
/// originY − row·pixelSizeY]; its sample value belongs to the pixel's centre.
/// This is GDAL's geotransform (originX, pixelSizeX, 0, originY, 0, −pixelSizeY).
struct Georeference {
    double originX = 0.0;     ///< Map x of the west edge of column 0.
    double originY = 0.0;     ///< Map y of the north edge of row 0.
    double pixelSizeX = 1.0;  ///< Map units per column, > 0.
    double pixelSizeY = 1.0;  ///< Map units per row, > 0; rows run south (map y falls).
    /// EPSG code of a projected CRS, or kUnknownProjectedCrs: projected, metres, no
    /// named CRS (GeoTIFF's "user-defined" ProjectedCRSGeoKey = 32767).
    int epsg = 0;

    static constexpr int kUnknownProjectedCrs = 0;

    bool operator==(const Georeference&) const = default;
};

}  // namespace terrain::io
