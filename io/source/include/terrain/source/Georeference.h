// Georeference: where a north-up raster lies on the map, as an affine pixel-to-map
// transform plus the CRS (its kind, EPSG code and WKT). Written into GeoTIFFs (GeoTIFF
// 1.1, OGC 19-008r4, §7).
#pragma once

#include <string>

namespace terrain::io {

/// What the map coordinates of a Georeference are.
enum class CrsKind {
    Unknown,     ///< No CRS known (e.g. a PNG height map): map units are samples.
    Projected,   ///< Easting/northing, usually metres.
    Geographic,  ///< Longitude (x) / latitude (y) in degrees.
};

/// A north-up raster's placement (no rotation). Pixels are areas (GeoTIFF
/// RasterPixelIsArea): pixel (col, row) covers map x in [originX + col·pixelSizeX,
/// originX + (col+1)·pixelSizeX] and map y in [originY − (row+1)·pixelSizeY,
/// originY − row·pixelSizeY]; its sample value belongs to the pixel's centre.
/// This is GDAL's geotransform (originX, pixelSizeX, 0, originY, 0, −pixelSizeY).
/// Sources whose samples are points on the edges (SRTM .hgt, GeoTIFF RasterPixelIsPoint)
/// are moved half a pixel north-west to this convention.
struct Georeference {
    double originX = 0.0;     ///< Map x of the west edge of column 0.
    double originY = 0.0;     ///< Map y of the north edge of row 0.
    double pixelSizeX = 1.0;  ///< Map units per column, > 0.
    double pixelSizeY = 1.0;  ///< Map units per row, > 0; rows run south (map y falls).
    /// EPSG code of the CRS (projected or geographic, as crsKind says), or
    /// kUnknownProjectedCrs (0): no named CRS. With crsKind Projected, 0 means projected,
    /// metres, no named CRS (GeoTIFF's "user-defined" ProjectedCRSGeoKey = 32767).
    int epsg = 0;
    /// Projected by default: a Georeference built without naming its kind is the
    /// projected, metre-based placement the GeoTIFF writer has always written.
    CrsKind crsKind = CrsKind::Projected;
    /// The CRS as OGC WKT when the source gave one (GDAL sources), else empty.
    std::string wkt{};

    static constexpr int kUnknownProjectedCrs = 0;
    static constexpr int kWgs84Geographic = 4326;

    bool operator==(const Georeference&) const = default;
};

/// "unknown", "projected" or "geographic".
constexpr const char* crsKindName(CrsKind kind) {
    switch (kind) {
        case CrsKind::Projected:
            return "projected";
        case CrsKind::Geographic:
            return "geographic";
        case CrsKind::Unknown:
            break;
    }
    return "unknown";
}

}  // namespace terrain::io
