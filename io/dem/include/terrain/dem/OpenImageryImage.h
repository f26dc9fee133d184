// openImageryImage: any raster GDAL opens (GeoTIFF, JPEG, PNG, VRT, a subdataset) as the
// RGBA8 image an imagery layer is built from (issue 47, docs/imagery.md, "Images").
#pragma once

#include "terrain/base/Result.h"
#include "terrain/source/ImageryImage.h"

#include <memory>
#include <string>

namespace terrain::io {

/// Opens `path` for a terrain placed as `placement` says. RGB, RGBA, grey (R = G = B) and
/// palette images of 8-bit bands; no-data and mask or alpha bands become alpha. Refused,
/// with a message naming the file: bands of 16 bits or floats (probably a DEM), an image
/// without georeference (unless placement.demExtent), a CRS PROJ cannot transform the
/// terrain's points into, a file GDAL cannot open or read.
Result<std::unique_ptr<ImageryImage>> openImageryImage(const std::string& path,
                                                       const ImageryPlacement& placement);

}  // namespace terrain::io
