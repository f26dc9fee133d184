// writeHeightImage: picks the format from the extension, checks the request, and runs the
// format's writer through an AtomicFile.
#include "terrain/dem/HeightImageWriter.h"

#include "HeightImageBackends.h"
#include "terrain/base/AtomicFile.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <string>

namespace terrain::io {

std::string_view formatName(HeightImageFormat format) {
    switch (format) {
        case HeightImageFormat::GeoTiff:
            return "geotiff";
        case HeightImageFormat::Png16:
            return "png16";
        case HeightImageFormat::Exr:
            return "exr";
        case HeightImageFormat::Hgt:
            return "hgt";
    }
    return "unknown";
}

Result<HeightImageFormat> heightImageFormatFor(const std::filesystem::path& path) {
    std::string extension = path.extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (extension == ".tif" || extension == ".tiff") return HeightImageFormat::GeoTiff;
    if (extension == ".png") return HeightImageFormat::Png16;
    if (extension == ".exr") return HeightImageFormat::Exr;
    if (extension == ".hgt") return HeightImageFormat::Hgt;
    return Error{fmt::format("{}: unknown output format '{}': use .tif, .tiff, .png, .exr or .hgt",
                             path.string(),
                             extension.empty() ? std::string("(no extension)") : extension)};
}

Result<HeightImageSummary> writeHeightImage(const std::filesystem::path& path, std::int64_t width,
                                            std::int64_t height, const HeightRowSource& source,
                                            const HeightImageOptions& options) {
    Result<HeightImageFormat> format = heightImageFormatFor(path);
    if (!format) return format.error();
    // Size limits: TIFF stores 32-bit dimensions; OpenImageIO (PNG, EXR) takes int.
    const std::int64_t limit = format.value() == HeightImageFormat::GeoTiff
                                   ? std::int64_t{std::numeric_limits<std::uint32_t>::max()}
                                   : std::int64_t{std::numeric_limits<int>::max()};
    if (width < 1 || height < 1 || width > limit || height > limit)
        return Error{
            fmt::format("{}: cannot write a {} × {} raster as {} (each side must be 1 to {})",
                        path.string(), width, height, formatName(format.value()), limit)};
    if (format.value() == HeightImageFormat::Hgt &&
        !(width == height && (width == 1201 || width == 3601)))
        return Error{
            fmt::format("{}: an SRTM .hgt tile is 1201 × 1201 (3\") or 3601 × 3601 (1\") "
                        "samples, not {} × {}",
                        path.string(), width, height)};
    if (format.value() == HeightImageFormat::Png16 &&
        (!std::isfinite(options.pngScaleM) || options.pngScaleM <= 0.0 ||
         (options.pngOffsetM && !std::isfinite(*options.pngOffsetM))))
        return Error{
            fmt::format("{}: the PNG height scale must be a positive number and the "
                        "offset a number (got scale {})",
                        path.string(), options.pngScaleM)};

    HeightImageSummary summary;
    summary.format = format.value();
    summary.width = width;
    summary.height = height;
    const Status written = writeAtomically(path, [&](const std::filesystem::path& file) -> Status {
        switch (summary.format) {
            case HeightImageFormat::GeoTiff:
                return detail::writeGeoTiff(file, path, width, height, source, options, summary);
            case HeightImageFormat::Png16:
                return detail::writePng16(file, path, width, height, source, options, summary);
            case HeightImageFormat::Exr:
                return detail::writeExr(file, path, width, height, source, options, summary);
            case HeightImageFormat::Hgt:
                return detail::writeHgt(file, path, width, height, source, options, summary);
        }
        return Error{fmt::format("{}: unknown format", path.string())};
    });
    if (!written) return written.error();
    return summary;
}

Result<HeightImageSummary> writeHeightImage(const std::filesystem::path& path, std::int64_t width,
                                            std::int64_t height, std::span<const float> heights,
                                            const HeightImageOptions& options) {
    TERRAIN_ASSERT(
        width >= 0 && height >= 0 &&
            heights.size() == static_cast<std::size_t>(width) * static_cast<std::size_t>(height),
        "heights do not match width × height");
    const HeightRowSource source = [&](std::int64_t firstRow, std::int64_t rowCount,
                                       std::span<float> out) {
        std::copy_n(heights.begin() + firstRow * width, rowCount * width, out.begin());
    };
    return writeHeightImage(path, width, height, source, options);
}

}  // namespace terrain::io
