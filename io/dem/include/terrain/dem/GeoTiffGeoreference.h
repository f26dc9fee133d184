// Reads the georeference of a GeoTIFF: the pixel scale, the tiepoint and the CRS kind
// and code (OpenImageIO 2.4 does not expose the GeoTIFF tags; this reads them with
// libtiff).
#pragma once

#include "terrain/base/Result.h"
#include "terrain/source/Georeference.h"

#include <filesystem>

namespace terrain::io {

/// The placement of a north-up GeoTIFF (ModelPixelScale + one ModelTiepoint; a
/// PixelIsPoint raster is shifted by half a pixel to the area convention of
/// Georeference). crsKind is Geographic for GTModelType 2 (or a GeographicTypeGeoKey
/// alone), Unknown when no key names a model or a CRS (openDem then takes the spacing as
/// metres and warns), Projected otherwise; epsg is the ProjectedCRSGeoKey
/// or GeographicTypeGeoKey (e.g. 4326), or kUnknownProjectedCrs when absent or
/// user-defined. wkt stays empty. Errors name the file: not a TIFF, no georeference,
/// rotated (a ModelTransformation). Any thread.
Result<Georeference> readGeoTiffGeoreference(const std::filesystem::path& path);

}  // namespace terrain::io
