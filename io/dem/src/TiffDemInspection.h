// What the DEM reader learns about a TIFF through libtiff before OpenImageIO decodes it:
// whether its sample type is a height type, whether every strip or tile lies inside the
// file (so a truncated file fails at open with a plain message), and the GeoTIFF
// georeference, GDAL no-data value and GDAL scale/offset that OpenImageIO 2.4 does not
// expose.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/source/Georeference.h"

#include <cstdint>
#include <optional>
#include <string>

namespace terrain::io::detail {

struct TiffDemFacts {
    std::optional<Georeference> georeference;
    std::optional<double> noDataValue;  ///< GDAL_NODATA (tag 42113)
    /// Band 1's scale and offset from GDAL_METADATA (tag 42112): heights are
    /// raw · scale + offset.
    std::optional<double> scale;
    std::optional<double> offset;
    /// Not north-up (a ModelTransformation, or a negative pixel scale: a flipped, rotated or
    /// sheared grid): the other facts are left unread, for GDAL, which reads such a grid
    /// (or refuses it by name), to take the file.
    bool flippedOrRotated = false;
    /// Samples per pixel: more than 1 is a multi-band image, read by GDAL, which chooses bands.
    int samplesPerPixel = 1;
};

/// Errors start with the path: not a TIFF (libtiff's message), an unsupported sample
/// type ("complex int16", "1-bit unsigned integer", …), "truncated: TIFF strip 3 ends
/// past the end of the file".
Result<TiffDemFacts> inspectTiffDem(const std::string& path, std::uint64_t fileBytes);

}  // namespace terrain::io::detail
