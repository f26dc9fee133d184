// GeoTIFF georeference reader through libtiff (GeoTIFF 1.1, OGC 19-008r4, §7).
#include "terrain/io/GeoTiffGeoreference.h"

#include "GeoTiffTags.h"
#include "TiffFile.h"

#include <fmt/format.h>

#include <cmath>
#include <span>
#include <string>

namespace terrain::io {

namespace {

constexpr std::uint16_t kGTRasterTypeKey = detail::kGTRasterTypeGeoKey;
constexpr std::uint16_t kRasterPixelIsPoint = 2;

// libtiff reads tags it does not know as "anonymous" fields whose count is a uint32
// (TIFF_VARIABLE2); a reader that registered them may have a uint16 count instead.
template <typename T>
std::span<const T> arrayTag(TIFF* tiff, ttag_t tag) {
    const TIFFField* field = TIFFFindField(tiff, tag, TIFF_ANY);
    if (field == nullptr || TIFFFieldPassCount(field) == 0) return {};
    void* data = nullptr;
    std::size_t count = 0;
    if (TIFFFieldReadCount(field) == TIFF_VARIABLE2) {
        std::uint32_t n = 0;
        if (TIFFGetField(tiff, tag, &n, &data) != 1) return {};
        count = n;
    } else {
        std::uint16_t n = 0;
        if (TIFFGetField(tiff, tag, &n, &data) != 1) return {};
        count = n;
    }
    return data == nullptr ? std::span<const T>()
                           : std::span<const T>(static_cast<const T*>(data), count);
}

}  // namespace

Result<Georeference> readGeoTiffGeoreference(const std::filesystem::path& path) {
    const auto fail = [&](const std::string& what) {
        return Error{fmt::format("{}: {}", path.string(), what)};
    };
    detail::TiffFile tiff(path, "r");
    if (!tiff) return fail(tiff.error("cannot open as a TIFF file"));
    TIFF* t = tiff.get();
    if (!arrayTag<double>(t, detail::kModelTransformationTag).empty())
        return fail("rotated or sheared rasters (GeoTIFF ModelTransformation) are not supported");
    const std::span<const double> scale = arrayTag<double>(t, detail::kModelPixelScaleTag);
    const std::span<const double> tiepoint = arrayTag<double>(t, detail::kModelTiepointTag);
    if (scale.size() < 2 || tiepoint.size() < 6)
        return fail("no GeoTIFF georeference (ModelPixelScale and ModelTiepoint tags)");
    if (!(scale[0] > 0.0) || !(scale[1] > 0.0) || !std::isfinite(scale[0]) ||
        !std::isfinite(scale[1]))
        return fail(
            fmt::format("GeoTIFF pixel scale ({}, {}) is not positive", scale[0], scale[1]));

    Georeference geo;
    geo.pixelSizeX = scale[0];
    geo.pixelSizeY = scale[1];
    // Tiepoint raster (I, J) ↔ map (X, Y): move it to raster (0, 0).
    geo.originX = tiepoint[3] - tiepoint[0] * scale[0];
    geo.originY = tiepoint[4] + tiepoint[1] * scale[1];

    const std::span<const std::uint16_t> keys =
        arrayTag<std::uint16_t>(t, detail::kGeoKeyDirectoryTag);
    if (keys.size() >= 4) {
        const std::size_t count = std::min<std::size_t>(keys[3], (keys.size() - 4) / 4);
        for (std::size_t k = 0; k < count; ++k) {
            const std::uint16_t id = keys[4 + 4 * k];
            const std::uint16_t location = keys[5 + 4 * k];
            const std::uint16_t value = keys[7 + 4 * k];
            if (location != 0) continue;  // only keys stored inline matter here
            if (id == detail::kProjectedCRSGeoKey && value != detail::kUserDefined)
                geo.epsg = value;
            if (id == kGTRasterTypeKey && value == kRasterPixelIsPoint) {
                // PixelIsPoint: the tiepoint is a pixel centre; the area convention wants
                // the corner, half a pixel north-west.
                geo.originX -= 0.5 * geo.pixelSizeX;
                geo.originY += 0.5 * geo.pixelSizeY;
            }
        }
    }
    return geo;
}

}  // namespace terrain::io
