// GeoTIFF height writer: float32 samples in 256×256 tiles with the GeoTIFF georeference
// tags, through libtiff. OpenImageIO 2.4's TIFF writer cannot emit the GeoTIFF tags (it
// drops attributes it does not know), so this format talks to libtiff directly.
#include "GeoTiffTags.h"
#include "HeightImageBackends.h"
#include "TiffFile.h"

#include <fmt/format.h>

#include <algorithm>
#include <string>
#include <vector>

namespace terrain::io::detail {

namespace {

constexpr std::uint32_t kTileSide = 256;
constexpr std::uint64_t kBigTiffThresholdBytes =
    (std::uint64_t{4} << 30U) - (std::uint64_t{256} << 20U);

// libtiff knows no GeoTIFF tags; they are declared on each handle before being set, as
// libgeotiff's XTIFF layer does. (TIFFFieldInfo wants mutable names.)
char kPixelScaleName[] = "ModelPixelScaleTag";
char kTiepointName[] = "ModelTiepointTag";
char kKeyDirectoryName[] = "GeoKeyDirectoryTag";
char kAsciiParamsName[] = "GeoAsciiParamsTag";
const TIFFFieldInfo kGeoTiffFields[] = {
    {kModelPixelScaleTag, TIFF_VARIABLE, TIFF_VARIABLE, TIFF_DOUBLE, FIELD_CUSTOM, 1, 1,
     kPixelScaleName},
    {kModelTiepointTag, TIFF_VARIABLE, TIFF_VARIABLE, TIFF_DOUBLE, FIELD_CUSTOM, 1, 1,
     kTiepointName},
    {kGeoKeyDirectoryTag, TIFF_VARIABLE, TIFF_VARIABLE, TIFF_SHORT, FIELD_CUSTOM, 1, 1,
     kKeyDirectoryName},
    {kGeoAsciiParamsTag, TIFF_VARIABLE, TIFF_VARIABLE, TIFF_ASCII, FIELD_CUSTOM, 1, 0,
     kAsciiParamsName},
};

// Citation of the CRS when no EPSG code is given.
constexpr const char* kUnknownCrsCitation = "unnamed projected CRS, metres|";

bool writeGeoreference(TIFF* tiff, const Georeference& geo) {
    if (TIFFMergeFieldInfo(tiff, kGeoTiffFields, 4) != 0) return false;
    // §7.3: one tiepoint (raster (0, 0) ↔ the map corner) and the pixel scale describe a
    // north-up raster; y scale is positive although map y falls down the rows.
    double scale[3] = {geo.pixelSizeX, geo.pixelSizeY, 0.0};
    double tiepoint[6] = {0.0, 0.0, 0.0, geo.originX, geo.originY, 0.0};
    const bool named = geo.epsg != Georeference::kUnknownProjectedCrs;
    // Keys sorted by id; each: id, location (0 = the value itself, or a tag), count, value.
    std::vector<std::uint16_t> keys = {1, 1, 1, 0};  // directory 1, revision 1.1, key count
    const auto key = [&](std::uint16_t id, std::uint16_t location, std::uint16_t count,
                         std::uint16_t value) {
        keys.insert(keys.end(), {id, location, count, value});
        ++keys[3];
    };
    key(kGTModelTypeGeoKey, 0, 1, kModelTypeProjected);
    key(kGTRasterTypeGeoKey, 0, 1, kRasterPixelIsArea);
    if (!named) {
        const auto length =
            static_cast<std::uint16_t>(std::char_traits<char>::length(kUnknownCrsCitation));
        key(kGTCitationGeoKey, static_cast<std::uint16_t>(kGeoAsciiParamsTag), length, 0);
    }
    key(kProjectedCRSGeoKey, 0, 1, named ? static_cast<std::uint16_t>(geo.epsg) : kUserDefined);
    if (!named) key(kProjLinearUnitsGeoKey, 0, 1, kLinearMetre);

    bool ok = TIFFSetField(tiff, kModelPixelScaleTag, 3, scale) == 1;
    ok = ok && TIFFSetField(tiff, kModelTiepointTag, 6, tiepoint) == 1;
    ok = ok &&
         TIFFSetField(tiff, kGeoKeyDirectoryTag, static_cast<int>(keys.size()), keys.data()) == 1;
    if (!named) ok = ok && TIFFSetField(tiff, kGeoAsciiParamsTag, kUnknownCrsCitation) == 1;
    return ok;
}

}  // namespace

Status writeGeoTiff(const std::filesystem::path& file, const std::filesystem::path& displayPath,
                    std::int64_t width, std::int64_t height, const HeightRowSource& source,
                    const HeightImageOptions& options, HeightImageSummary& summary) {
    const auto fail = [&](const std::string& what) {
        return Error{fmt::format("{}: cannot write GeoTIFF: {}", displayPath.string(), what)};
    };
    const std::uint64_t rawBytes =
        static_cast<std::uint64_t>(width) * static_cast<std::uint64_t>(height) * sizeof(float);
    const bool bigTiff =
        options.bigTiff == BigTiffMode::Always ||
        (options.bigTiff == BigTiffMode::Automatic && rawBytes >= kBigTiffThresholdBytes);
    if (!bigTiff && rawBytes >= kBigTiffThresholdBytes &&
        options.tiffCompression == TiffCompression::None)
        return fail("the raster needs BigTIFF (over 4 GiB) but BigTIFF was turned off");
    if (options.georeference &&
        (options.georeference->epsg < 0 || options.georeference->epsg >= kUserDefined))
        return fail(fmt::format("EPSG code {} does not fit a GeoTIFF key (1 to {})",
                                options.georeference->epsg, kUserDefined - 1));

    TiffFile tiff(file, bigTiff ? "w8" : "w");
    if (!tiff) return fail(tiff.error("cannot create the file"));
    TIFF* t = tiff.get();
    bool ok = TIFFSetField(t, TIFFTAG_IMAGEWIDTH, static_cast<std::uint32_t>(width)) == 1;
    ok = ok && TIFFSetField(t, TIFFTAG_IMAGELENGTH, static_cast<std::uint32_t>(height)) == 1;
    ok = ok && TIFFSetField(t, TIFFTAG_SAMPLESPERPIXEL, 1) == 1;
    ok = ok && TIFFSetField(t, TIFFTAG_BITSPERSAMPLE, 32) == 1;
    ok = ok && TIFFSetField(t, TIFFTAG_SAMPLEFORMAT, SAMPLEFORMAT_IEEEFP) == 1;
    ok = ok && TIFFSetField(t, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK) == 1;
    ok = ok && TIFFSetField(t, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG) == 1;
    ok = ok && TIFFSetField(t, TIFFTAG_TILEWIDTH, kTileSide) == 1;
    ok = ok && TIFFSetField(t, TIFFTAG_TILELENGTH, kTileSide) == 1;
    ok = ok && TIFFSetField(t, TIFFTAG_SOFTWARE, "terrain io") == 1;
    if (options.tiffCompression == TiffCompression::Deflate) {
        ok = ok && TIFFSetField(t, TIFFTAG_COMPRESSION, COMPRESSION_ADOBE_DEFLATE) == 1;
        ok = ok && TIFFSetField(t, TIFFTAG_PREDICTOR, PREDICTOR_FLOATINGPOINT) == 1;
    } else {
        ok = ok && TIFFSetField(t, TIFFTAG_COMPRESSION, COMPRESSION_NONE) == 1;
    }
    if (ok && options.georeference) ok = writeGeoreference(t, *options.georeference);
    if (!ok) return fail(tiff.error("libtiff refused a tag"));

    // One tile row at a time: ask the source for 256 rows, cut them into tiles.
    const auto tileColumns = static_cast<std::int64_t>((width + kTileSide - 1) / kTileSide);
    std::vector<float> band(static_cast<std::size_t>(width) * kTileSide);
    std::vector<float> tile(static_cast<std::size_t>(kTileSide) * kTileSide);
    HeightStats stats;
    for (std::int64_t row0 = 0; row0 < height; row0 += kTileSide) {
        const std::int64_t rows = std::min<std::int64_t>(kTileSide, height - row0);
        const std::span<float> bandRows(band.data(), static_cast<std::size_t>(width * rows));
        source(row0, rows, bandRows);
        stats.add(bandRows);
        for (std::int64_t tx = 0; tx < tileColumns; ++tx) {
            const std::int64_t col0 = tx * kTileSide;
            const std::int64_t cols = std::min<std::int64_t>(kTileSide, width - col0);
            std::fill(tile.begin(), tile.end(), 0.0F);  // edge tiles: pad with 0
            for (std::int64_t r = 0; r < rows; ++r) {
                std::copy_n(band.begin() + r * width + col0, cols, tile.begin() + r * kTileSide);
            }
            const ttile_t index = TIFFComputeTile(t, static_cast<std::uint32_t>(col0),
                                                  static_cast<std::uint32_t>(row0), 0, 0);
            if (TIFFWriteEncodedTile(t, index, tile.data(),
                                     static_cast<tmsize_t>(tile.size() * sizeof(float))) < 0)
                return fail(tiff.error("writing a tile failed"));
        }
        if (options.progress)
            options.progress(static_cast<double>(row0 + rows) / static_cast<double>(height));
    }
    if (!tiff.close()) return fail(tiff.error("closing the file failed"));
    stats.storeIn(summary);
    summary.bigTiff = bigTiff;
    return {};
}

}  // namespace terrain::io::detail
