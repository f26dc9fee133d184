// Reads the georeference of a GeoTIFF: the pixel scale, the tiepoint and the projected
// CRS code (OpenImageIO 2.4 does not expose the GeoTIFF tags; this reads them with
// libtiff).
#pragma once

#include "terrain/io/Georeference.h"
#include "terrain/io/Result.h"

#include <filesystem>

namespace terrain::io {

/// The placement of a north-up GeoTIFF (ModelPixelScale + one ModelTiepoint; a
/// PixelIsPoint raster is shifted by half a pixel to the area convention of
/// Georeference). epsg is the ProjectedCRSGeoKey, or kUnknownProjectedCrs when absent or
/// user-defined. Errors name the file: not a TIFF, no georeference, rotated (a
/// ModelTransformation). Any thread.
Result<Georeference> readGeoTiffGeoreference(const std::filesystem::path& path);

}  // namespace terrain::io
