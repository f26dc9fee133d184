// GdalImageryImage: openImageryImage over GDAL (OpenImageryImage.h). A palette image is
// expanded to RGBA through an in-memory VRT (gdal_translate -expand rgba) so that averaging
// works on colours, not indices; averaged blocks come from RasterIO with GRIORA_Average,
// which uses the file's overviews where it has them and leaves masked pixels out.
#include "terrain/dem/OpenImageryImage.h"

#include "GdalSession.h"
#include "ImageFileTruncation.h"

#include <fmt/format.h>
#include <gdal_utils.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <optional>
#include <vector>

namespace terrain::io {
namespace {

using detail::GdalDataset;
using detail::GdalErrorCapture;

constexpr double kImageryNaN = std::numeric_limits<double>::quiet_NaN();

struct ImageryTransformDeleter {
    void operator()(OGRCoordinateTransformation* t) const {
        OGRCoordinateTransformation::DestroyCT(t);
    }
};
using ImageryTransform = std::unique_ptr<OGRCoordinateTransformation, ImageryTransformDeleter>;

std::string imageryCrsName(const OGRSpatialReference& crs) {
    const char* name = crs.GetName();
    return name != nullptr && *name != '\0' ? std::string(name) : std::string("unnamed CRS");
}

// "truncated: …" when a block of a GeoTIFF lies past the end of its file (GDAL would read the
// blocks before it and fail only when a tile reaches the cut), or a PNG or JPEG is cut
// (ImageFileTruncation.h). Reads the TIFF's block table, never pixels.
std::optional<std::string> findImageryTruncation(GDALDataset* ds, const std::string& path) {
    std::error_code ec;
    const auto fileBytes = std::filesystem::file_size(path, ec);
    if (ec) return std::nullopt;  // not a plain file (a VRT's sources are checked by GDAL)
    const std::string driver = ds->GetDriver() ? ds->GetDriver()->GetDescription() : "";
    if (driver == "PNG") return detail::findPngTruncation(path, fileBytes);
    if (driver == "JPEG") return detail::findJpegTruncation(path, fileBytes);
    if (driver != "GTiff") return std::nullopt;
    const char* interleave = ds->GetMetadataItem("INTERLEAVE", "IMAGE_STRUCTURE");
    const int bands =
        interleave != nullptr && std::string(interleave) == "BAND" ? ds->GetRasterCount() : 1;
    for (int b = 1; b <= bands; ++b) {
        GDALRasterBand* band = ds->GetRasterBand(b);
        int bw = 0, bh = 0;
        band->GetBlockSize(&bw, &bh);
        const int nx = (ds->GetRasterXSize() + bw - 1) / bw,
                  ny = (ds->GetRasterYSize() + bh - 1) / bh;
        for (int y = 0; y < ny; ++y)
            for (int x = 0; x < nx; ++x) {
                const char* offset =
                    band->GetMetadataItem(fmt::format("BLOCK_OFFSET_{}_{}", x, y).c_str(), "TIFF");
                const char* size =
                    band->GetMetadataItem(fmt::format("BLOCK_SIZE_{}_{}", x, y).c_str(), "TIFF");
                if (offset == nullptr || size == nullptr) continue;  // sparse
                const unsigned long long end =
                    std::strtoull(offset, nullptr, 10) + std::strtoull(size, nullptr, 10);
                if (end > fileBytes)
                    return fmt::format(
                        "truncated: block ({}, {}) of band {} ends at byte {}, past "
                        "the end of the file ({} bytes)",
                        x, y, b, end, fileBytes);
            }
    }
    return std::nullopt;
}

class GdalImageryImage final : public ImageryImage {
public:
    std::string m_name;
    GdalDataset m_dataset;   // as opened
    GdalDataset m_expanded;  // the palette expanded to RGBA, when it had one
    GDALDataset* m_read = nullptr;
    std::array<int, 3> m_colourBands{1, 1, 1};
    int m_alphaBand = 0;  // 0: the mask band of band 1 (all valid: 255)
    bool m_maskAllValid = true;
    std::int64_t m_width = 0, m_height = 0;
    ImageryPlacement m_placement;
    // Terrain to pixels: the terrain's map coordinates (planar) or lon/lat (globe), through
    // m_toImage when the CRSs differ, then the inverse geotransform.
    std::array<double, 6> m_gt{}, m_inverseGt{};
    ImageryTransform m_toImage, m_toTerrain;
    bool m_wraps = false;
    std::vector<int> m_success;
    std::vector<std::uint8_t> m_band;

    const std::string& name() const override { return m_name; }
    std::int64_t width() const override { return m_width; }
    std::int64_t height() const override { return m_height; }
    bool wrapsColumns() const override { return m_wraps; }

    void toPixels(std::span<double> xs, std::span<double> ys) override {
        if (m_placement.demExtent) {
            // The image's outer edges on the DEM's first and last samples.
            const double sx =
                static_cast<double>(m_width) / static_cast<double>(m_placement.rasterWidth - 1);
            const double sy =
                static_cast<double>(m_height) / static_cast<double>(m_placement.rasterHeight - 1);
            for (std::size_t i = 0; i < xs.size(); ++i) {
                xs[i] *= sx;
                ys[i] *= sy;
            }
            return;
        }
        if (!m_placement.globe) {
            const Georeference& g = m_placement.georeference;
            for (std::size_t i = 0; i < xs.size(); ++i) {
                xs[i] = g.originX + (xs[i] + 0.5) * g.pixelSizeX;
                ys[i] = g.originY - (ys[i] + 0.5) * g.pixelSizeY;
            }
        }
        if (m_toImage) {
            m_success.assign(xs.size(), 0);
            m_toImage->Transform(static_cast<int>(xs.size()), xs.data(), ys.data(), nullptr,
                                 m_success.data());
            for (std::size_t i = 0; i < xs.size(); ++i)
                if (!m_success[i]) xs[i] = ys[i] = kImageryNaN;
        }
        for (std::size_t i = 0; i < xs.size(); ++i) {
            const double x = xs[i], y = ys[i];
            xs[i] = m_inverseGt[0] + x * m_inverseGt[1] + y * m_inverseGt[2];
            ys[i] = m_inverseGt[3] + x * m_inverseGt[4] + y * m_inverseGt[5];
        }
    }

    std::array<double, 2> toTerrain(double px, double py) override {
        if (m_placement.demExtent)
            return {px * static_cast<double>(m_placement.rasterWidth - 1) /
                        static_cast<double>(m_width),
                    py * static_cast<double>(m_placement.rasterHeight - 1) /
                        static_cast<double>(m_height)};
        double x = m_gt[0] + px * m_gt[1] + py * m_gt[2];
        double y = m_gt[3] + px * m_gt[4] + py * m_gt[5];
        if (m_toTerrain) {
            int ok = 0;
            m_toTerrain->Transform(1, &x, &y, nullptr, &ok);
            if (!ok) return {kImageryNaN, kImageryNaN};
        }
        if (m_placement.globe) return {x, y};
        const Georeference& g = m_placement.georeference;
        return {(x - g.originX) / g.pixelSizeX - 0.5, (g.originY - y) / g.pixelSizeY - 0.5};
    }

    Status readBlocks(std::int64_t bx0, std::int64_t by0, int w, int h, int k,
                      std::span<std::uint8_t> rgba) override {
        const std::int64_t px0 = bx0 << k, py0 = by0 << k;
        const std::int64_t px1 = std::min(m_width, (bx0 + w) << k);
        const std::int64_t py1 = std::min(m_height, (by0 + h) << k);
        GDALRasterIOExtraArg extra;
        INIT_RASTERIO_EXTRA_ARG(extra);
        extra.eResampleAlg = k > 0 ? GRIORA_Average : GRIORA_NearestNeighbour;
        GdalErrorCapture errors;
        const auto readBand = [&](GDALRasterBand* band, int channel) {
            return band->RasterIO(GF_Read, static_cast<int>(px0), static_cast<int>(py0),
                                  static_cast<int>(px1 - px0), static_cast<int>(py1 - py0),
                                  rgba.data() + channel, w, h, GDT_Byte, 4,
                                  static_cast<GSpacing>(w) * 4, &extra) == CE_None;
        };
        bool ok = true;
        for (int c = 0; c < 3 && ok; ++c)
            ok = readBand(m_read->GetRasterBand(m_colourBands[static_cast<std::size_t>(c)]), c);
        if (ok) {
            if (m_alphaBand > 0) {
                ok = readBand(m_read->GetRasterBand(m_alphaBand), 3);
            } else if (m_maskAllValid) {
                for (std::size_t i = 3; i < rgba.size(); i += 4) rgba[i] = 255;
            } else {
                ok = readBand(m_read->GetRasterBand(1)->GetMaskBand(), 3);
            }
        }
        if (!ok)
            return Error{fmt::format("{}: cannot read pixels [{}, {}) × [{}, {}): {}", m_name, px0,
                                     px1, py0, py1, errors.message("read error"))};
        return {};
    }
};

}  // namespace

Result<std::unique_ptr<ImageryImage>> openImageryImage(const std::string& path,
                                                       const ImageryPlacement& placement) {
    detail::ensureGdalRegistered();
    GdalErrorCapture errors;
    auto image = std::make_unique<GdalImageryImage>();
    image->m_name = path;
    image->m_placement = placement;
    image->m_dataset.reset(GDALDataset::FromHandle(
        GDALOpenEx(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, nullptr, nullptr, nullptr)));
    if (!image->m_dataset)
        return Error{fmt::format("{}: cannot open as an image: {}", path,
                                 errors.message("GDAL does not recognise it"))};
    GDALDataset* ds = image->m_dataset.get();
    if (const auto truncated = findImageryTruncation(ds, path))
        return Error{fmt::format("{}: {}", path, *truncated)};
    if (ds->GetRasterCount() == 0) {
        char** subdatasets = ds->GetMetadata("SUBDATASETS");
        if (subdatasets != nullptr && subdatasets[0] != nullptr) {
            const char* first = std::strchr(subdatasets[0], '=');
            return Error{fmt::format("{}: holds several images (subdatasets); name one, e.g. {}",
                                     path, first ? first + 1 : subdatasets[0])};
        }
        return Error{fmt::format("{}: holds no raster band", path)};
    }
    for (int b = 1; b <= ds->GetRasterCount(); ++b) {
        const GDALDataType type = ds->GetRasterBand(b)->GetRasterDataType();
        if (type != GDT_Byte)
            return Error{fmt::format(
                "{}: band {} holds {} samples, not 8-bit colours: probably a DEM or other data, "
                "not imagery. Scale it to 8 bits first, e.g. gdal_translate -ot Byte -scale "
                "{} image.tif",
                path, b, GDALGetDataTypeName(type), path)};
    }
    image->m_width = ds->GetRasterXSize();
    image->m_height = ds->GetRasterYSize();
    image->m_read = ds;

    // Bands: palette, RGB(A), grey(+alpha).
    GDALRasterBand* first = ds->GetRasterBand(1);
    if (first->GetColorInterpretation() == GCI_PaletteIndex && first->GetColorTable() != nullptr) {
        const char* argv[] = {"-of", "VRT", "-expand", "rgba", nullptr};
        GDALTranslateOptions* options = GDALTranslateOptionsNew(const_cast<char**>(argv), nullptr);
        image->m_expanded.reset(GDALDataset::FromHandle(
            GDALTranslate("", GDALDataset::ToHandle(ds), options, nullptr)));
        GDALTranslateOptionsFree(options);
        if (!image->m_expanded)
            return Error{fmt::format("{}: cannot expand its palette: {}", path,
                                     errors.message("GDALTranslate failed"))};
        image->m_read = image->m_expanded.get();
        image->m_colourBands = {1, 2, 3};
        image->m_alphaBand = 4;
    } else if (ds->GetRasterCount() >= 3) {
        image->m_colourBands = {1, 2, 3};
        if (ds->GetRasterCount() >= 4 &&
            (ds->GetRasterBand(4)->GetColorInterpretation() == GCI_AlphaBand ||
             ds->GetRasterCount() == 4))
            image->m_alphaBand = 4;
    } else if (ds->GetRasterCount() == 2 &&
               ds->GetRasterBand(2)->GetColorInterpretation() == GCI_AlphaBand) {
        image->m_alphaBand = 2;
    }
    if (image->m_alphaBand == 0)
        image->m_maskAllValid = (first->GetMaskFlags() & GMF_ALL_VALID) != 0;

    // Placement.
    if (placement.demExtent) {
        if (placement.globe)
            return Error{
                fmt::format("{}: placing an image on the DEM's extent works on a planar "
                            "pyramid only; a globe needs a georeferenced image",
                            path)};
        return std::unique_ptr<ImageryImage>(std::move(image));
    }
    const OGRSpatialReference* imageCrs = ds->GetSpatialRef();
    if (ds->GetGeoTransform(image->m_gt.data()) != CE_None || imageCrs == nullptr ||
        imageCrs->IsEmpty())
        return Error{
            fmt::format("{}: has no georeference (no geotransform and CRS), so it "
                        "cannot be placed on the terrain; on a planar pyramid, "
                        "--dem-extent lays it over the DEM's extent",
                        path)};
    if (!GDALInvGeoTransform(image->m_gt.data(), image->m_inverseGt.data()))
        return Error{fmt::format("{}: its geotransform cannot be inverted", path)};
    OGRSpatialReference terrainCrs;
    if (placement.globe) {
        terrainCrs.importFromEPSG(Georeference::kWgs84Geographic);
    } else {
        const Georeference& g = placement.georeference;
        const bool known = !g.wkt.empty() ? terrainCrs.importFromWkt(g.wkt.c_str()) == OGRERR_NONE
                           : g.epsg != 0  ? terrainCrs.importFromEPSG(g.epsg) == OGRERR_NONE
                                          : false;
        if (!known || g.crsKind == CrsKind::Unknown)
            return Error{
                fmt::format("{}: the pyramid has no CRS (built from a DEM without "
                            "georeference), so a georeferenced image cannot be placed "
                            "on it; --dem-extent lays it over the DEM's extent",
                            path)};
    }
    terrainCrs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    OGRSpatialReference ownCrs(*imageCrs);
    ownCrs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    if (!ownCrs.IsSame(&terrainCrs)) {
        image->m_toImage.reset(OGRCreateCoordinateTransformation(&terrainCrs, &ownCrs));
        image->m_toTerrain.reset(OGRCreateCoordinateTransformation(&ownCrs, &terrainCrs));
        if (!image->m_toImage || !image->m_toTerrain)
            return Error{
                fmt::format("{}: PROJ cannot transform the terrain's CRS ({}) into the "
                            "image's ({}): {}",
                            path, imageryCrsName(terrainCrs), imageryCrsName(ownCrs),
                            errors.message("no coordinate operation"))};
    }
    image->m_wraps =
        ownCrs.IsGeographic() && image->m_gt[2] == 0.0 && image->m_gt[4] == 0.0 &&
        std::abs(std::abs(image->m_gt[1]) * static_cast<double>(image->m_width) - 360.0) < 1e-6;
    return std::unique_ptr<ImageryImage>(std::move(image));
}

}  // namespace terrain::io
