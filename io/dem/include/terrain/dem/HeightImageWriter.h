// HeightImageWriter: writes a height raster (metres, float) as a GeoTIFF, a 16-bit PNG,
// an OpenEXR file or an SRTM .hgt tile, chosen by the extension, band by band so that rasters far
// larger than memory (a 16,385² DEM) can be written. Every file goes through AtomicFile.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/source/Georeference.h"

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string_view>

namespace terrain::io {

enum class HeightImageFormat {
    GeoTiff,  ///< .tif/.tiff: float32, 256×256 tiles, GeoTIFF tags, BigTIFF when needed.
    Png16,    ///< .png: uint16 grey = round((h − offset) / scale), clamped to [0, 65535].
    Exr,      ///< .exr: float32, one channel named "Y" (greyscale in every EXR viewer).
    /// .hgt: an SRTM tile, 1201² (3″) or 3601² (1″) big-endian int16 whole metres, rounded
    /// and clamped to ±32767 (−32768 is SRTM's void); the name gives the place (N46W122.hgt).
    Hgt,
};

/// "geotiff", "png16", "exr" or "hgt".
std::string_view formatName(HeightImageFormat format);

/// The format for path's extension (case-insensitive); an Error naming path otherwise.
Result<HeightImageFormat> heightImageFormatFor(const std::filesystem::path& path);

/// Fills rows [firstRow, firstRow + rowCount) of the image into `out` (rowCount × width
/// floats, row-major, row 0 = the top/north row). Called from the writing thread with
/// consecutive bands; the PNG writer without a given offset reads the image twice (once
/// to find its minimum).
using HeightRowSource =
    std::function<void(std::int64_t firstRow, std::int64_t rowCount, std::span<float> out)>;

enum class TiffCompression {
    None,
    Deflate,  ///< zlib with the floating-point predictor (TIFF Technical Note 3); lossless.
};

enum class BigTiffMode {
    Automatic,  ///< BigTIFF when the raw samples reach 4 GiB − 256 MiB.
    Always,
    Never,
};

struct HeightImageOptions {
    /// GeoTIFF only: written as ModelPixelScale, ModelTiepoint and GeoKeyDirectory.
    std::optional<Georeference> georeference;
    TiffCompression tiffCompression = TiffCompression::Deflate;
    BigTiffMode bigTiff = BigTiffMode::Automatic;
    /// PNG only: metres per grey level. 0.1 m as in the Puget Sound PNG heightmaps.
    double pngScaleM = 0.1;
    /// PNG only: height of grey level 0; default floor(minimum height of the image).
    std::optional<double> pngOffsetM;
    /// Rows asked of the source at a time (GeoTIFF bands are whole 256-row tile rows).
    /// Memory use is about width × bandRows × 4 bytes.
    std::int64_t bandRows = 256;
    /// Called after each band with the fraction of the work done, in (0, 1].
    std::function<void(double fraction)> progress;
};

/// The PNG's grey levels: height ≈ offsetM + grey × scaleM.
struct PngQuantisation {
    double scaleM = 0.1;
    double offsetM = 0.0;
    std::uint64_t clampedSamples = 0;  ///< Outside [0, 65535] grey levels, or not finite.
};

struct HeightImageSummary {
    HeightImageFormat format = HeightImageFormat::GeoTiff;
    std::int64_t width = 0;
    std::int64_t height = 0;
    float minHeightM = 0.0F;  ///< Over the finite samples.
    float maxHeightM = 0.0F;
    std::uint64_t nonFiniteSamples = 0;
    std::optional<PngQuantisation> png;
    bool bigTiff = false;
};

/// Writes a width × height raster from `source` to `path`, in the format its extension
/// names. Errors (unknown extension, unwritable folder, library failures) name path and
/// leave nothing behind. Calling thread.
Result<HeightImageSummary> writeHeightImage(const std::filesystem::path& path, std::int64_t width,
                                            std::int64_t height, const HeightRowSource& source,
                                            const HeightImageOptions& options = {});

/// The same for a raster already in memory (row-major, width × height floats).
Result<HeightImageSummary> writeHeightImage(const std::filesystem::path& path, std::int64_t width,
                                            std::int64_t height, std::span<const float> heights,
                                            const HeightImageOptions& options = {});

}  // namespace terrain::io
