// GeoTIFF georeference reader through libtiff (GeoTIFF 1.1, OGC 19-008r4, §7).
#include "terrain/dem/GeoTiffGeoreference.h"

#include "GeoTiffGeoreferenceTags.h"
#include "GeoTiffTags.h"
#include "TiffFile.h"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>

namespace terrain::io {

namespace {

constexpr std::uint16_t kGTRasterTypeKey = detail::kGTRasterTypeGeoKey;
constexpr std::uint16_t kRasterPixelIsPoint = 2;
constexpr std::uint16_t kGeographicTypeGeoKey = 2048;  // §7.4.3 GeodeticCRSGeoKey
constexpr std::uint16_t kModelTypeGeographic = 2;

// The TIFF type a tag's values must have to be read as T.
template <typename T>
constexpr TIFFDataType tiffTypeOf() {
    if constexpr (std::is_same_v<T, double>) return TIFF_DOUBLE;
    if constexpr (std::is_same_v<T, std::uint16_t>) return TIFF_SHORT;
    if constexpr (std::is_same_v<T, char>) return TIFF_ASCII;
}

// libtiff reads tags it does not know as "anonymous" fields whose count is a uint32
// (TIFF_VARIABLE2); a reader that registered them may have a uint16 count instead. An
// anonymous field keeps the type the file declares, so a tag of another type than T (a
// ModelPixelScale stored as LONG) reads as absent: read as T it would run past its values
// (found by fuzz-dem-tiff, tests/fuzz/dem-tiff/pixel-scale-of-type-long.tif).
template <typename T>
std::span<const T> arrayTag(TIFF* tiff, ttag_t tag) {
    const TIFFField* field = TIFFFindField(tiff, tag, TIFF_ANY);
    if (field == nullptr || TIFFFieldPassCount(field) == 0) return {};
    if (TIFFFieldDataType(field) != tiffTypeOf<T>()) return {};
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

// The CRS keys that decide the kind and EPSG code; absent keys stay 0.
struct CrsKeys {
    std::uint16_t modelType = 0;
    std::uint16_t projected = 0;
    std::uint16_t geographic = 0;
    bool pixelIsPoint = false;
};

CrsKeys readCrsKeys(TIFF* tiff) {
    CrsKeys crs;
    const std::span<const std::uint16_t> keys =
        arrayTag<std::uint16_t>(tiff, detail::kGeoKeyDirectoryTag);
    if (keys.size() < 4) return crs;
    const std::size_t count = std::min<std::size_t>(keys[3], (keys.size() - 4) / 4);
    for (std::size_t k = 0; k < count; ++k) {
        const std::uint16_t id = keys[4 + 4 * k];
        const std::uint16_t location = keys[5 + 4 * k];
        const std::uint16_t value = keys[7 + 4 * k];
        if (location != 0) continue;  // only keys stored inline matter here
        if (id == detail::kGTModelTypeGeoKey) crs.modelType = value;
        if (id == detail::kProjectedCRSGeoKey) crs.projected = value;
        if (id == kGeographicTypeGeoKey) crs.geographic = value;
        if (id == kGTRasterTypeKey) crs.pixelIsPoint = value == kRasterPixelIsPoint;
    }
    return crs;
}

}  // namespace

namespace detail {

bool hasFlippedOrRotatedPlacement(TIFF* t) {
    if (!arrayTag<double>(t, kModelTransformationTag).empty()) return true;
    const std::span<const double> scale = arrayTag<double>(t, kModelPixelScaleTag);
    return scale.size() >= 2 && (scale[0] < 0.0 || scale[1] < 0.0);
}

Result<std::optional<Georeference>> readGeoreferenceTags(TIFF* t) {
    if (!arrayTag<double>(t, kModelTransformationTag).empty())
        return Error{"rotated or sheared rasters (GeoTIFF ModelTransformation) are not supported"};
    const std::span<const double> scale = arrayTag<double>(t, kModelPixelScaleTag);
    const std::span<const double> tiepoint = arrayTag<double>(t, kModelTiepointTag);
    if (scale.size() < 2 || tiepoint.size() < 6) return std::optional<Georeference>();
    if (!(scale[0] > 0.0) || !(scale[1] > 0.0) || !std::isfinite(scale[0]) ||
        !std::isfinite(scale[1]))
        return Error{
            fmt::format("GeoTIFF pixel scale ({}, {}) is not positive", scale[0], scale[1])};

    Georeference geo;
    geo.pixelSizeX = scale[0];
    geo.pixelSizeY = scale[1];
    // Tiepoint raster (I, J) ↔ map (X, Y): move it to raster (0, 0).
    geo.originX = tiepoint[3] - tiepoint[0] * scale[0];
    geo.originY = tiepoint[4] + tiepoint[1] * scale[1];

    const CrsKeys crs = readCrsKeys(t);
    // Without a model type, a geographic code alone says geographic; a projected code or
    // the model type alone keeps the writer's convention: projected, metres, maybe unnamed.
    // No CRS key at all is an unknown CRS (the reader's caller takes the spacing as metres
    // and says so).
    const bool geographic = crs.modelType == kModelTypeGeographic ||
                            (crs.modelType == 0 && crs.projected == 0 && crs.geographic != 0);
    const bool noCrs = crs.modelType == 0 && crs.projected == 0 && crs.geographic == 0;
    if (noCrs) {
        geo.crsKind = CrsKind::Unknown;
    } else if (geographic) {
        geo.crsKind = CrsKind::Geographic;
        if (crs.geographic != 0 && crs.geographic != kUserDefined) geo.epsg = crs.geographic;
    } else if (crs.modelType == 0 || crs.modelType == kModelTypeProjected) {
        geo.crsKind = CrsKind::Projected;
        if (crs.projected != 0 && crs.projected != kUserDefined) geo.epsg = crs.projected;
    } else {
        geo.crsKind = CrsKind::Unknown;  // geocentric or a private model type
    }
    if (crs.pixelIsPoint) {
        // PixelIsPoint: the tiepoint is a pixel centre; the area convention wants the
        // corner, half a pixel north-west.
        geo.originX -= 0.5 * geo.pixelSizeX;
        geo.originY += 0.5 * geo.pixelSizeY;
    }
    return std::optional<Georeference>(geo);
}

std::optional<std::string> readAsciiTag(TIFF* tiff, ttag_t tag) {
    const TIFFField* field = TIFFFindField(tiff, tag, TIFF_ANY);
    if (field == nullptr || TIFFFieldDataType(field) != TIFF_ASCII) return std::nullopt;
    if (TIFFFieldPassCount(field) != 0) {
        const std::span<const char> chars = arrayTag<char>(tiff, tag);
        if (chars.empty()) return std::nullopt;
        std::string text(chars.data(), chars.size());
        while (!text.empty() && text.back() == '\0') text.pop_back();
        return text;
    }
    const char* value = nullptr;
    if (TIFFGetField(tiff, tag, &value) != 1 || value == nullptr) return std::nullopt;
    return std::string(value);
}

std::optional<double> readGdalNoDataTag(TIFF* tiff) {
    const std::optional<std::string> tag = readAsciiTag(tiff, kGdalNoDataTag);
    if (!tag) return std::nullopt;
    std::string_view text = *tag;
    while (!text.empty() && (text.back() == '\0' || text.back() == ' ')) text.remove_suffix(1);
    while (!text.empty() && text.front() == ' ') text.remove_prefix(1);
    if (text == "nan" || text == "NaN" || text == "-nan") return std::nan("");
    double value = 0.0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (error != std::errc() || end != text.data() + text.size()) return std::nullopt;
    return value;
}

}  // namespace detail

Result<Georeference> readGeoTiffGeoreference(const std::filesystem::path& path) {
    const auto fail = [&](const std::string& what) {
        return Error{fmt::format("{}: {}", path.string(), what)};
    };
    detail::TiffFile tiff(path, "r");
    if (!tiff) return fail(tiff.error("cannot open as a TIFF file"));
    Result<std::optional<Georeference>> geo = detail::readGeoreferenceTags(tiff.get());
    if (!geo) return fail(geo.error().message);
    if (!geo.value())
        return fail("no GeoTIFF georeference (ModelPixelScale and ModelTiepoint tags)");
    return *geo.value();
}

}  // namespace terrain::io
