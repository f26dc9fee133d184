// Several DEM files as one raster: after checking that every input shares the first
// one's CRS, pixel size and grid, GDALBuildVRT makes an in-memory VRT over them and the
// GDAL reader reads it. Inputs may overlap (SRTM tiles share their edge rows); samples
// no input covers read as NaN.
#include "terrain/dem/OpenDem.h"
#include "GdalDemReader.h"

#include <fmt/format.h>
#include <gdal_utils.h>
#include <ogr_spatialref.h>

#include <cmath>
#include <vector>

namespace terrain::io::detail {

namespace {

// Pixel sizes agree when equal to about 9 digits (text formats round them).
constexpr double kPixelSizeTolerance = 1e-9;
// Grids are aligned when origins differ by whole pixels, to this fraction of a pixel.
constexpr double kAlignmentTolerancePixels = 1e-3;

struct MosaicInput {
    std::string path;
    DemInfo info;
    GdalDataset dataset;
};

std::string crsLabel(const MosaicInput& input) {
    const Georeference& geo = input.info.georeference;
    const OGRSpatialReference* srs = input.dataset->GetSpatialRef();
    std::string name = geo.epsg != 0 ? fmt::format("EPSG:{}", geo.epsg)
                       : (srs != nullptr && srs->GetName() != nullptr) ? std::string(srs->GetName())
                                                                       : std::string("none");
    return fmt::format("{} ({})", name, crsKindName(geo.crsKind));
}

bool sameCrs(const MosaicInput& a, const MosaicInput& b) {
    const OGRSpatialReference* sa = a.dataset->GetSpatialRef();
    const OGRSpatialReference* sb = b.dataset->GetSpatialRef();
    const bool emptyA = sa == nullptr || sa->IsEmpty(), emptyB = sb == nullptr || sb->IsEmpty();
    if (emptyA || emptyB)
        return emptyA == emptyB && a.info.georeference.crsKind == b.info.georeference.crsKind &&
               a.info.georeference.epsg == b.info.georeference.epsg;
    return sa->IsSame(sb) != 0;
}

bool samePixelSize(double a, double b) {
    return std::abs(a - b) <= kPixelSizeTolerance * std::max(std::abs(a), std::abs(b));
}

// Checks input `i` against input 0 (same CRS, pixel size, grid).
Status checkCompatible(const MosaicInput& first, const MosaicInput& input) {
    const Georeference& g0 = first.info.georeference;
    const Georeference& g = input.info.georeference;
    if (!sameCrs(first, input))
        return Error{fmt::format("{}: CRS {} differs from {}'s CRS {}; a mosaic needs one CRS",
                                 input.path, crsLabel(input), first.path, crsLabel(first))};
    if (!samePixelSize(g.pixelSizeX, g0.pixelSizeX) || !samePixelSize(g.pixelSizeY, g0.pixelSizeY))
        return Error{fmt::format(
            "{}: pixel size {} × {} differs from {}'s pixel size {} × {}; a mosaic needs one "
            "pixel size",
            input.path, g.pixelSizeX, g.pixelSizeY, first.path, g0.pixelSizeX, g0.pixelSizeY)};
    const double dx = (g.originX - g0.originX) / g0.pixelSizeX;
    const double dy = (g0.originY - g.originY) / g0.pixelSizeY;
    if (std::abs(dx - std::round(dx)) > kAlignmentTolerancePixels ||
        std::abs(dy - std::round(dy)) > kAlignmentTolerancePixels)
        return Error{fmt::format(
            "{}: grid is not aligned with {}'s: origin ({}, {}) is ({:.4f}, {:.4f}) pixels from "
            "({}, {})",
            input.path, first.path, g.originX, g.originY, dx, dy, g0.originX, g0.originY)};
    return {};
}

}  // namespace

DemReaderResult openGdalMosaic(const std::vector<std::string>& paths,
                               const DemOpenOptions& options) {
    TERRAIN_ASSERT(!paths.empty(), "openGdalMosaic: no inputs");
    ensureGdalRegistered();
    std::vector<MosaicInput> inputs;
    inputs.reserve(paths.size());
    for (const std::string& path : paths) {
        Result<GdalDataset> opened = openGdalDataset(path, options.maxDecodeBytes);
        if (!opened) return opened.error();
        GdalDataset dataset = std::move(opened).value();
        Result<DemInfo> info = describeGdalDataset(*dataset, path, options.band);
        if (!info) return info.error();
        if (!info.value().hasGeoreference)
            return Error{
                fmt::format("{}: no georeference; every input of a mosaic needs one", path)};
        if (info.value().rowsFlipped || info.value().columnsFlipped)
            return Error{
                fmt::format("{}: rows run north or columns west; mosaics need north-up "
                            "inputs (gdalwarp makes one)",
                            path)};
        inputs.push_back(MosaicInput{path, std::move(info).value(), std::move(dataset)});
        if (inputs.size() > 1)
            if (Status s = checkCompatible(inputs.front(), inputs.back()); !s) return s.error();
    }

    std::vector<const char*> names;
    for (const std::string& path : paths) names.push_back(path.c_str());
    GdalErrorCapture errors;
    GDALBuildVRTOptions* vrtOptions = GDALBuildVRTOptionsNew(nullptr, nullptr);
    int usageError = 0;
    GdalDataset vrt(GDALDataset::FromHandle(GDALBuildVRT(
        "", static_cast<int>(names.size()), nullptr, names.data(), vrtOptions, &usageError)));
    GDALBuildVRTOptionsFree(vrtOptions);
    if (!vrt)
        return Error{fmt::format("{}: cannot build the mosaic of {} inputs: {}", paths.front(),
                                 paths.size(), errors.message("GDALBuildVRT failed"))};
    Result<DemInfo> described = describeGdalDataset(*vrt, paths.front(), options.band);
    if (!described) return described.error();
    DemInfo info = std::move(described).value();
    info.inputs = paths;
    // The VRT carries the first input's CRS; keep the description read from the file.
    info.georeference.crsKind = inputs.front().info.georeference.crsKind;
    info.georeference.epsg = inputs.front().info.georeference.epsg;
    info.georeference.wkt = inputs.front().info.georeference.wkt;
    info.sampleType = inputs.front().info.sampleType;
    info.warnings = inputs.front().info.warnings;  // the band warning, once

    // Footprints, to find gaps: without a VRT no-data value GDAL fills them with 0.
    std::vector<PixelRect> footprints;
    double coveredSamples = 0.0;
    for (const MosaicInput& input : inputs) {
        const Georeference& g = input.info.georeference;
        PixelRect rect;
        rect.x =
            std::llround((g.originX - info.georeference.originX) / info.georeference.pixelSizeX);
        rect.y =
            std::llround((info.georeference.originY - g.originY) / info.georeference.pixelSizeY);
        rect.width = input.info.width;
        rect.height = input.info.height;
        coveredSamples += static_cast<double>(rect.width) * static_cast<double>(rect.height);
        footprints.push_back(rect);
    }
    bool overlaps = false;
    for (std::size_t i = 0; i < footprints.size() && !overlaps; ++i) {
        for (std::size_t j = i + 1; j < footprints.size() && !overlaps; ++j) {
            const PixelRect& a = footprints[i];
            const PixelRect& b = footprints[j];
            overlaps = a.x < b.x + b.width && b.x < a.x + a.width && a.y < b.y + b.height &&
                       b.y < a.y + a.height;
        }
    }
    const bool mayHaveGaps = overlaps || coveredSamples != static_cast<double>(info.width) *
                                                               static_cast<double>(info.height);
    if (!mayHaveGaps || info.noDataValue) footprints.clear();

    if (Status s = applyDemOpenOptions(info, options); !s) return s.error();
    return std::unique_ptr<DemReader>(
        std::make_unique<GdalDemReader>(std::move(info), std::move(vrt), std::move(footprints)));
}

}  // namespace terrain::io::detail
