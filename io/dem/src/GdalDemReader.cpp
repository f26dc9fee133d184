// DEM reader for anything GDAL opens (netCDF, VRT, DTED, subdatasets, /vsi… paths, ...):
// one band (band 1 unless chosen) read as float windows through RasterIO, rows and columns
// flipped to north-up where the geotransform runs the other way, no-data and scale/offset
// from the band, the placement from the geotransform and the CRS from the dataset's spatial
// reference.
#include "GdalDemReader.h"
#include "NetCdfClassicExtent.h"
#include "terrain/dem/OpenDem.h"
#include "terrain/source/DemSampleConversion.h"

#include <cpl_string.h>
#include <fmt/format.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <optional>
#include <string_view>
#include <system_error>
#include <vector>

namespace terrain::io::detail {

namespace {

const char* sampleTypeName(GDALDataType type) {
    switch (type) {
        case GDT_Byte:
            return "uint8";
        case GDT_UInt16:
            return "uint16";
        case GDT_Int16:
            return "int16";
        case GDT_UInt32:
            return "uint32";
        case GDT_Int32:
            return "int32";
        case GDT_UInt64:
            return "uint64";
        case GDT_Int64:
            return "int64";
        case GDT_Float32:
            return "float32";
        case GDT_Float64:
            return "float64";
        default:
            return nullptr;
    }
}

// CF grids with longitude/latitude axes and no grid_mapping (ETOPO, most global
// netCDF): GDAL reports no CRS, yet the axes' units say degrees. CF leaves the datum
// unstated; like GDAL for the axes it recognises, we take WGS 84.
bool hasCfLongitudeLatitudeAxes(GDALDataset& dataset) {
    bool east = false, north = false;
    for (CSLConstList item = dataset.GetMetadata(); item != nullptr && *item != nullptr; ++item) {
        const std::string_view entry(*item);
        const std::size_t equals = entry.find('=');
        if (equals == std::string_view::npos) continue;
        const std::string_view key = entry.substr(0, equals), value = entry.substr(equals + 1);
        if (!key.ends_with("#units")) continue;
        if (value == "degrees_east" || value == "degree_east" || value == "degrees_E" ||
            value == "degree_E")
            east = true;
        if (value == "degrees_north" || value == "degree_north" || value == "degrees_N" ||
            value == "degree_N")
            north = true;
    }
    return east && north;
}

void describeCrs(GDALDataset& dataset, Georeference& geo) {
    const OGRSpatialReference* srs = dataset.GetSpatialRef();
    if (srs == nullptr || srs->IsEmpty()) {
        geo.crsKind = CrsKind::Unknown;
        if (!hasCfLongitudeLatitudeAxes(dataset)) return;
        geo.crsKind = CrsKind::Geographic;
        geo.epsg = Georeference::kWgs84Geographic;
        OGRSpatialReference wgs84;
        if (wgs84.importFromEPSG(Georeference::kWgs84Geographic) == OGRERR_NONE)
            geo.wkt = wktOf(wgs84);
        return;
    }
    // A local (engineering) CRS is a plane in linear units: what the GeoTIFF writer calls
    // an unnamed projected CRS (GDAL reads its files back as one), so Projected too.
    geo.crsKind = srs->IsGeographic()                    ? CrsKind::Geographic
                  : srs->IsProjected() || srs->IsLocal() ? CrsKind::Projected
                                                         : CrsKind::Unknown;
    const char* authority = srs->GetAuthorityName(nullptr);
    const char* code = srs->GetAuthorityCode(nullptr);
    if (authority != nullptr && code != nullptr && EQUAL(authority, "EPSG"))
        geo.epsg = std::atoi(code);
    geo.wkt = wktOf(*srs);
}

// The names a container lists for its subdatasets (its SUBDATASETS metadata's *_NAME
// entries), as a user gives them: NETCDF:"f.nc":elevation.
std::vector<std::string> subdatasetNames(GDALDataset& dataset) {
    std::vector<std::string> names;
    for (CSLConstList item = dataset.GetMetadata("SUBDATASETS");
         item != nullptr && *item != nullptr; ++item) {
        const std::string_view entry(*item);
        const std::size_t equals = entry.find('=');
        if (equals == std::string_view::npos || !entry.substr(0, equals).ends_with("_NAME"))
            continue;
        names.emplace_back(entry.substr(equals + 1));
    }
    return names;
}

std::string subdatasetList(const std::vector<std::string>& names) {
    std::string list;
    for (const std::string& name : names) list += fmt::format("\n  {}", name);
    return list;
}

bool isRegularFile(const std::string& path) {
    std::error_code error;
    return !path.empty() && std::filesystem::is_regular_file(path, error);
}

// The file a subdataset name points into, and the name's part that picks the subdataset
// inside it: DRIVER:"file":part (netCDF, HDF5), DRIVER:file:part, or DRIVER:part:file
// (GTIFF_DIR:2:f.tif). Nothing when no part of the name is an existing file.
struct SubdatasetName {
    std::string container;
    std::string part;
};

std::optional<SubdatasetName> splitSubdatasetName(const std::string& name) {
    const std::size_t driverEnd = name.find(':');
    if (driverEnd == std::string::npos) return std::nullopt;
    const std::string rest = name.substr(driverEnd + 1);
    if (rest.starts_with('"')) {
        const std::size_t close = rest.find('"', 1);
        if (close == std::string::npos) return std::nullopt;
        const std::string file = rest.substr(1, close - 1);
        std::string part = rest.substr(close + 1);
        if (part.starts_with(':')) part.erase(0, 1);
        if (!isRegularFile(file)) return std::nullopt;
        return SubdatasetName{file, part};
    }
    const std::size_t last = rest.rfind(':');
    if (last == std::string::npos) return std::nullopt;
    if (isRegularFile(rest.substr(0, last)))
        return SubdatasetName{rest.substr(0, last), rest.substr(last + 1)};
    const std::size_t first = rest.find(':');
    if (isRegularFile(rest.substr(first + 1)))
        return SubdatasetName{rest.substr(first + 1), rest.substr(0, first)};
    return std::nullopt;
}

// A subdataset name GDAL cannot open whose file opens: said in our words with the file's
// subdatasets (what a container opened without one lists), not the driver's (netCDF's
// "netcdf error #-49 … netcdfdataset.cpp" for a variable the file lacks). Nothing when the
// file does not open or lists the name after all (GDAL's own message is then the better one).
std::optional<Error> missingSubdataset(const std::string& name) {
    const std::optional<SubdatasetName> split = splitSubdatasetName(name);
    if (!split) return std::nullopt;
    GdalErrorCapture errors;  // the container's own complaints are not the user's problem
    GdalDataset container(
        GDALDataset::Open(split->container.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
    if (!container) return std::nullopt;
    const std::vector<std::string> names = subdatasetNames(*container);
    if (std::find(names.begin(), names.end(), name) != names.end()) return std::nullopt;
    const std::string missing = split->part.empty() ? std::string("the subdataset")
                                                    : fmt::format("subdataset {}", split->part);
    if (names.empty())
        return Error{fmt::format(
            "{}: {} does not exist: {} holds no subdatasets; give the file itself as the input",
            name, missing, split->container)};
    return Error{fmt::format(
        "{}: {} does not exist: {} holds {} subdatasets; give one of them as the input:{}", name,
        missing, split->container, names.size(), subdatasetList(names))};
}

}  // namespace

std::optional<double> metresPerHeightUnit(std::string_view unit) {
    std::string lower;
    for (const char c : unit)
        lower.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
    while (!lower.empty() && std::isspace(static_cast<unsigned char>(lower.back())))
        lower.pop_back();
    for (const char* name : {"", "m", "metre", "metres", "meter", "meters", "m above sea level"})
        if (lower == name) return 1.0;
    for (const char* name : {"km", "kilometre", "kilometres", "kilometer", "kilometers"})
        if (lower == name) return 1000.0;
    for (const char* name : {"ft", "foot", "feet", "international foot", "ft (international)"})
        if (lower == name) return 0.3048;
    for (const char* name : {"us survey foot", "us_survey_foot", "ftus", "us-ft", "survey foot"})
        if (lower == name) return 1200.0 / 3937.0;
    return std::nullopt;
}

Result<DemInfo> describeGdalDataset(GDALDataset& dataset, const std::string& path,
                                    std::optional<int> bandNumber, RotatedGrids rotated) {
    const auto fail = [&](const std::string& what) {
        return Error{fmt::format("{}: {}", path, what)};
    };
    const int bands = dataset.GetRasterCount();
    if (bands < 1) {
        // A container (netCDF or HDF with several variables, a multi-page TIFF): name what
        // a user could open instead, as gdalinfo lists it.
        const std::vector<std::string> names = subdatasetNames(dataset);
        if (!names.empty())
            return fail(fmt::format(
                "holds {} subdatasets and no raster band of its own; give one of them as the "
                "input:{}",
                names.size(), subdatasetList(names)));
        return fail("GDAL finds no raster band in it");
    }
    const int bandIndex = bandNumber.value_or(1);
    // Band 0 and negative bands are refused here, with the file's band count, rather than by
    // the command line's parser, which knows nothing of the file.
    if (bandIndex < 1 || bandIndex > bands)
        return fail(fmt::format("band {} does not exist: {}", bandIndex,
                                bands == 1 ? std::string("it has one band, band 1")
                                           : fmt::format("bands are numbered 1 to {}", bands)));
    GDALRasterBand* band = dataset.GetRasterBand(bandIndex);
    const GDALDataType type = band->GetRasterDataType();
    const char* typeName = sampleTypeName(type);
    if (typeName == nullptr)
        return fail(fmt::format("unsupported sample type: {}{}", GDALGetDataTypeName(type),
                                GDALDataTypeIsComplex(type) != 0 ? " (complex)" : ""));

    DemInfo info;
    info.path = path;
    info.readerName = "gdal";
    info.inputs = {path};
    info.band = bandIndex;
    info.bandCount = bands;
    if (bands > 1 && !bandNumber) {
        const char* colour = GDALGetColorInterpretationName(band->GetColorInterpretation());
        info.warnings.push_back(fmt::format(
            "{}: {} bands; heights are read from band 1{}; choose another with -b/--band N", path,
            bands,
            colour != nullptr && std::string_view(colour) != "Undefined"
                ? fmt::format(" ({})", colour)
                : std::string()));
    }
    info.width = dataset.GetRasterXSize();
    info.height = dataset.GetRasterYSize();
    info.sampleType = typeName;
    if (info.width <= 0 || info.height <= 0)
        return fail(fmt::format("empty raster ({} × {})", info.width, info.height));
    int has = 0;
    const double noData = band->GetNoDataValue(&has);
    if (has != 0) info.noDataValue = noData;
    const double scale = band->GetScale(&has);
    if (has != 0 && scale != 0.0) info.vertical.scale = scale;
    const double offset = band->GetOffset(&has);
    if (has != 0) info.vertical.offset = offset;
    // Heights in the band's unit (netCDF/CF `units`, GeoTIFF's vertical unit), after the
    // scale and offset: metres from there on.
    const std::optional<double> metres = metresPerHeightUnit(band->GetUnitType());
    if (!metres)
        return fail(
            fmt::format("height unit \"{}\" is not a length this reader knows (m, km, ft, "
                        "US survey ft); give the heights' scale with --vertical-scale",
                        band->GetUnitType()));
    info.vertical.scale *= *metres;
    info.vertical.offset *= *metres;

    info.georeference.crsKind = CrsKind::Unknown;
    std::array<double, 6> gt{};
    if (dataset.GetGeoTransform(gt.data()) != CE_None) return info;  // not georeferenced
    if (gt[2] != 0.0 || gt[4] != 0.0) {
        if (rotated == RotatedGrids::Refuse)
            return fail(fmt::format(
                "rotated or sheared rasters are not supported here (geotransform {}, {}, {}, {}, "
                "{}, {}); resample it onto a north-up grid first (gdalwarp)",
                gt[0], gt[1], gt[2], gt[3], gt[4], gt[5]));
        if (!std::all_of(gt.begin(), gt.end(), [](double v) { return std::isfinite(v); }) ||
            gt[1] * gt[5] - gt[2] * gt[4] == 0.0)
            return fail(fmt::format("unusable geotransform {}, {}, {}, {}, {}, {}", gt[0], gt[1],
                                    gt[2], gt[3], gt[4], gt[5]));
        // Placed by openResampledGdalDem once the warper's grid is chosen.
        info.resampledFrom = ResampledGrid{info.width, info.height, gt, {}, "bilinear"};
        describeCrs(dataset, info.georeference);
        return info;
    }
    if (gt[1] == 0.0 || gt[5] == 0.0 || !std::isfinite(gt[1]) || !std::isfinite(gt[5]))
        return fail(fmt::format("unusable pixel size {} × {} in the geotransform", gt[1], gt[5]));
    Georeference& geo = info.georeference;
    geo.pixelSizeX = std::abs(gt[1]);
    geo.pixelSizeY = std::abs(gt[5]);
    // Rows running north and columns running west are flipped on read, so the north and
    // west edges are the far ends.
    info.rowsFlipped = gt[5] > 0.0;
    info.columnsFlipped = gt[1] < 0.0;
    geo.originX = info.columnsFlipped ? gt[0] + gt[1] * static_cast<double>(info.width) : gt[0];
    geo.originY = info.rowsFlipped ? gt[3] + gt[5] * static_cast<double>(info.height) : gt[3];
    describeCrs(dataset, geo);
    info.hasGeoreference = true;
    return info;
}

GdalDemReader::GdalDemReader(DemInfo info, GdalDataset dataset, std::vector<PixelRect> coverage,
                             int datasetBand)
    : m_info(std::move(info)),
      m_dataset(std::move(dataset)),
      m_band(m_dataset->GetRasterBand(datasetBand > 0 ? datasetBand : m_info.band)),
      m_coverage(std::move(coverage)) {
    const GDALDataType type = m_band->GetRasterDataType();
    m_wide = type == GDT_Float64 || type == GDT_Int32 || type == GDT_UInt32 || type == GDT_Int64 ||
             type == GDT_UInt64;
}

Status GdalDemReader::readWindow(std::int64_t x0, std::int64_t y0, std::int64_t width,
                                 std::int64_t rows, std::span<float> out) {
    assertDemWindow(m_info, x0, y0, width, rows, out);
    if (width == 0 || rows == 0) return {};
    const std::size_t count = static_cast<std::size_t>(width * rows);
    const std::int64_t sourceY = m_info.rowsFlipped ? m_info.height - y0 - rows : y0;
    const std::int64_t sourceX = m_info.columnsFlipped ? m_info.width - x0 - width : x0;
    void* target = out.data();
    if (m_wide) {
        m_wideScratch.resize(count);
        target = m_wideScratch.data();
    }
    GdalErrorCapture errors;
    const CPLErr result = m_band->RasterIO(
        GF_Read, static_cast<int>(sourceX), static_cast<int>(sourceY), static_cast<int>(width),
        static_cast<int>(rows), target, static_cast<int>(width), static_cast<int>(rows),
        m_wide ? GDT_Float64 : GDT_Float32, 0, 0, nullptr);
    if (result != CE_None)
        return Error{
            fmt::format("{}: cannot read rows {}..{}: {}", m_info.path, y0, y0 + rows - 1,
                        libraryMessage(errors.message("GDAL RasterIO failed"), m_info.path))};
    if (m_wide)
        convertDemSamples(m_wideScratch.data(), count, out.data(), m_info.vertical,
                          m_info.noDataValue);
    else
        convertDemSamples(out.data(), count, out.data(), m_info.vertical, m_info.noDataValue);
    if (m_info.rowsFlipped) {
        for (std::int64_t r = 0; r < rows / 2; ++r)
            std::swap_ranges(out.data() + r * width, out.data() + (r + 1) * width,
                             out.data() + (rows - 1 - r) * width);
    }
    if (m_info.columnsFlipped) {
        for (std::int64_t r = 0; r < rows; ++r)
            std::reverse(out.data() + r * width, out.data() + (r + 1) * width);
    }
    if (!m_coverage.empty()) maskUncovered(x0, y0, width, rows, out);
    return {};
}

void GdalDemReader::maskUncovered(std::int64_t x0, std::int64_t y0, std::int64_t width,
                                  std::int64_t rows, std::span<float> out) const {
    std::vector<unsigned char> covered(static_cast<std::size_t>(width));
    for (std::int64_t r = 0; r < rows; ++r) {
        const std::int64_t y = y0 + r;
        std::fill(covered.begin(), covered.end(), 0);
        for (const PixelRect& rect : m_coverage) {
            if (y < rect.y || y >= rect.y + rect.height) continue;
            const std::int64_t a = std::max(x0, rect.x),
                               b = std::min(x0 + width, rect.x + rect.width);
            if (a < b) std::fill(covered.begin() + (a - x0), covered.begin() + (b - x0), 1);
        }
        float* row = out.data() + r * width;
        for (std::int64_t x = 0; x < width; ++x)
            if (covered[static_cast<std::size_t>(x)] == 0)
                row[x] = std::numeric_limits<float>::quiet_NaN();
    }
}

namespace {

// GDAL's ASCII grid drivers (AAIGrid, GRASSASCIIGrid and ISG, all in frmts/aaigrid) find a
// line by first reading every unknown line before it, recursively, and learn where a line
// starts only when the line before it parsed. In a file that breaks off early, reading line
// n therefore costs 2^n reads: a 210-byte grid whose header promises 61 rows spun for
// minutes (fuzz-dem-asc; tests/fuzz/dem-asc/). Reading the rows in order once at open costs
// one parse of the file, turns such a file into an error naming the row, and leaves every
// later read, in any order and through any handle of the file, the linear case.
// GDAL decodes and caches whole blocks, and a damaged header can make one gigabytes: a
// 300-byte file GDAL took for an NGS geoid grid of 1,283,027,553 columns asked for a 5.1 GB
// line (found by fuzz-dem-asc). The OpenImageIO reader's limit applies, before any read.
// A pixel-interleaved file decodes a block of every band at once (GDAL's GTiff driver keeps
// one buffer for all of them): a 1.4 KB TIFF claiming 16,129 float32 samples a pixel in
// 256 × 256 tiles made it allocate 4.2 GB to read band 1 (found by fuzz-dem-tiff).
Status checkBlockBytes(GDALDataset& dataset, const std::string& path,
                       std::uint64_t maxDecodeBytes) {
    if (dataset.GetRasterCount() < 1) return {};  // describeGdalDataset names it
    GDALRasterBand* band = dataset.GetRasterBand(1);
    int blockColumns = 0, blockRows = 0;
    band->GetBlockSize(&blockColumns, &blockRows);
    const char* interleave = dataset.GetMetadataItem("INTERLEAVE", "IMAGE_STRUCTURE");
    const bool pixelInterleaved = interleave != nullptr && std::string_view(interleave) == "PIXEL";
    const std::uint64_t bandsDecoded =
        pixelInterleaved ? std::uint64_t(dataset.GetRasterCount()) : 1;
    const std::uint64_t blockBytes =
        std::uint64_t(std::max(blockColumns, 0)) * std::uint64_t(std::max(blockRows, 0)) *
        std::uint64_t(GDALGetDataTypeSizeBytes(band->GetRasterDataType())) * bandsDecoded;
    if (blockBytes <= maxDecodeBytes) return {};
    return Error{fmt::format(
        "{}: {} × {} samples{} in blocks of {} × {}: a block decodes to {} MiB, more than the "
        "{} MiB a read may take (a damaged header?)",
        path, dataset.GetRasterXSize(), dataset.GetRasterYSize(),
        bandsDecoded > 1 ? fmt::format(" of {} interleaved bands", bandsDecoded) : "", blockColumns,
        blockRows, blockBytes >> 20U, maxDecodeBytes >> 20U)};
}

Status checkTextGridRows(GDALDataset& dataset, const std::string& path) {
    const GDALDriver* driver = dataset.GetDriver();
    const std::string_view name = driver != nullptr ? driver->GetDescription() : "";
    if (name != "AAIGrid" && name != "GRASSASCIIGrid" && name != "ISG") return {};
    GDALRasterBand* band = dataset.GetRasterBand(1);
    if (band == nullptr) return {};  // describeGdalDataset names it
    const int rows = dataset.GetRasterYSize();
    GdalErrorCapture errors;
    double sample = 0.0;
    for (int y = 0; y < rows; ++y) {
        if (band->RasterIO(GF_Read, 0, y, 1, 1, &sample, 1, 1, GDT_Float64, 0, 0, nullptr) !=
            CE_None)
            return Error{fmt::format("{}: row {} of the {} its header promises cannot be read: {}",
                                     path, y, rows,
                                     libraryMessage(errors.message("GDAL cannot read it"), path))};
    }
    return {};
}

}  // namespace

Result<GdalDataset> openGdalDataset(const std::string& path, std::uint64_t maxDecodeBytes) {
    std::error_code missing;
    if (!isGdalDatasetName(path) || std::filesystem::exists(path, missing)) {
        const Result<std::uint64_t> size = checkDemInputFile(path);
        if (!size) return size.error();
        const Result<std::optional<std::uint64_t>> end = netCdfClassicDataEnd(path);
        if (!end) return end.error();
        if (end.value() && *end.value() > size.value())
            return Error{fmt::format(
                "{}: truncated: the netCDF variables' data ends at byte {}, the file has {} bytes",
                path, *end.value(), size.value())};
    }
    ensureGdalRegistered();
    GdalErrorCapture errors;
    GdalDataset dataset(
        GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY | GDAL_OF_VERBOSE_ERROR));
    if (!dataset) {
        if (isGdalDatasetName(path))
            if (std::optional<Error> refusal = missingSubdataset(path)) return *refusal;
        return Error{
            fmt::format("{}: {}", path,
                        libraryMessage(errors.message("GDAL cannot open it as a raster"), path))};
    }
    if (Status blocks = checkBlockBytes(*dataset, path, maxDecodeBytes); !blocks)
        return blocks.error();
    if (Status rows = checkTextGridRows(*dataset, path); !rows) return rows.error();
    return dataset;
}

DemReaderResult openGdalDem(const std::string& path, const DemOpenOptions& options) {
    Result<GdalDataset> opened = openGdalDataset(path, options.maxDecodeBytes);
    if (!opened) return opened.error();
    GdalDataset dataset = std::move(opened).value();
    Result<DemInfo> info =
        describeGdalDataset(*dataset, path, options.band, RotatedGrids::Resample);
    if (!info) return info.error();
    if (info.value().resampledFrom)
        return openResampledGdalDem(std::move(info).value(), std::move(dataset), options);
    if (Status s = applyDemOpenOptions(info.value(), options); !s) return s.error();
    return std::unique_ptr<DemReader>(
        std::make_unique<GdalDemReader>(std::move(info).value(), std::move(dataset)));
}

}  // namespace terrain::io::detail
