// The GeoTIFF tags of a TIFF that is already open with libtiff: the georeference
// (GeoTIFF 1.1, OGC 19-008r4, §7) and GDAL's no-data tag. Shared by
// readGeoTiffGeoreference and the DEM reader, which opens the file once for both.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/source/Georeference.h"

#include <tiffio.h>

#include <optional>
#include <string>

namespace terrain::io::detail {

inline constexpr ttag_t kGdalMetadataTag = 42112;  // ASCII, GDAL's <GDALMetadata> XML
inline constexpr ttag_t kGdalNoDataTag = 42113;    // ASCII, e.g. "-32768"

/// The placement of a north-up GeoTIFF, nullopt when it has no ModelPixelScale +
/// ModelTiepoint. Errors (their message without the file name): a ModelTransformation
/// (rotated or sheared), a pixel scale that is not positive.
Result<std::optional<Georeference>> readGeoreferenceTags(TIFF* tiff);

/// Whether the TIFF's grid is not north-up: placed by a ModelTransformation matrix (what
/// rotated, sheared and some flipped grids use), or by a negative ModelPixelScale (GDAL writes
/// one for columns running west).
bool hasFlippedOrRotatedPlacement(TIFF* tiff);

/// The text of an ASCII tag (also one libtiff does not know), nullopt when absent.
std::optional<std::string> readAsciiTag(TIFF* tiff, ttag_t tag);

/// GDAL_NODATA (tag 42113) as a number, nullopt when absent or not a number.
std::optional<double> readGdalNoDataTag(TIFF* tiff);

}  // namespace terrain::io::detail
