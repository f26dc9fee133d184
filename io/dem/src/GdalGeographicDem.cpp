// Projected sources on the globe (issue 20): a globe pyramid is built from longitude/latitude
// grids on WGS84, so a projected DEM (UTM, Lambert, a national grid) or a rotated geographic
// one is resampled by GDAL's warper, bilinearly and window by window, onto a geographic grid
// that holds every one of its samples at its finest ground spacing. As for a rotated grid
// (GdalResampledDem.cpp), the source's own samples stay readable and each is placed on the
// new grid through the CRS transform (PROJ, through OGR), so the pyramid's Err(P) is made
// and checked against the samples the user gave, not against the resampled grid.
#include "GdalDemReader.h"
#include "GdalWarp.h"
#include "terrain/dem/OpenDem.h"
#include "terrain/globe/Wgs84.h"

#include <fmt/format.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <memory>
#include <numbers>
#include <span>
#include <string>
#include <vector>

namespace terrain::io::detail {
namespace {

struct CoordinateTransformDeleter {
    void operator()(OGRCoordinateTransformation* t) const {
        OGRCoordinateTransformation::DestroyCT(t);
    }
};
using CoordinateTransform =
    std::unique_ptr<OGRCoordinateTransformation, CoordinateTransformDeleter>;

// WGS84's meridional (M) and prime-vertical (N) radii of curvature at a latitude, metres.
terrain::globe::CurvatureRadii radiiAt(double latitudeDeg) {
    return terrain::globe::Wgs84::curvatureRadiiAt(latitudeDeg);
}

// The source's own samples and where each lies in longitude and latitude.
class SamplePlacer {
public:
    SamplePlacer(const std::array<double, 6>& geoTransform, CoordinateTransform toWgs84)
        : m_gt(geoTransform), m_toWgs84(std::move(toWgs84)) {}

    // Longitudes and latitudes (degrees) of samples (c, r) of the lists, in place; false
    // where the transform fails for one of them.
    bool place(std::span<const double> columns, std::span<const double> rows,
               std::vector<double>& longitude, std::vector<double>& latitude) const {
        longitude.resize(columns.size());
        latitude.resize(columns.size());
        for (std::size_t i = 0; i < columns.size(); ++i) {
            const double c = columns[i] + 0.5, r = rows[i] + 0.5;  // the pixel's centre
            longitude[i] = m_gt[0] + c * m_gt[1] + r * m_gt[2];
            latitude[i] = m_gt[3] + c * m_gt[4] + r * m_gt[5];
        }
        m_success.assign(columns.size(), 0);
        if (!m_toWgs84->Transform(static_cast<int>(columns.size()), longitude.data(),
                                  latitude.data(), nullptr, m_success.data()))
            return false;
        // PROJ can report success for a point it maps off the planet (a damaged or
        // degenerate CRS: a latitude of 1e228 was seen); such a point is not placed either.
        for (std::size_t i = 0; i < columns.size(); ++i)
            if (m_success[i] == 0 || !std::isfinite(longitude[i]) ||
                !(std::abs(latitude[i]) <= 90.0))
                return false;
        return true;
    }

private:
    std::array<double, 6> m_gt;
    CoordinateTransform m_toWgs84;
    mutable std::vector<int> m_success;
};

// What to call the CRS in a message: its name, or for an unnamed one its projection method
// (a netCDF grid_mapping is often "unknown" with a Transverse Mercator inside).
std::string crsLabel(const OGRSpatialReference& crs) {
    const char* name = crs.GetName();
    if (name != nullptr && *name != '\0' && std::string(name) != "unknown") return name;
    const char* method = crs.GetAttrValue("PROJECTION");
    return method != nullptr ? fmt::format("projected ({})", method) : "projected";
}

struct GeographicTarget {
    double west = 0.0, north = 0.0, pixelLon = 0.0, pixelLat = 0.0;
    std::int64_t width = 0, height = 0;
};

// The pole a grid goes round (every longitude, from the pole to the footprint), if any.
enum class Pole { None, North, South };

// The longitude/latitude grid whose first and last sample centres are the extremes of the
// source's sample centres, so every source sample lies inside it (the bounds then cover
// each one), with the source's finest ground spacing along both axes wherever it lies. A
// footprint around a pole (a polar stereographic grid) holds every longitude: its grid wraps
// all 360° and reaches the pole, as a global grid's does.
Result<GeographicTarget> targetFor(const std::string& path, const SamplePlacer& placer,
                                   std::int64_t width, std::int64_t height) {
    // The edges sample by sample (up to 8,192 a side), in order around the grid, and a
    // 33 × 33 lattice inside: where a conformal projection's footprint reaches furthest,
    // whether it goes round a pole, and where its scale is finest.
    std::vector<double> cols, rows;
    const auto along = [](std::int64_t n, std::int64_t most) {
        std::vector<double> at;
        const std::int64_t step = std::max<std::int64_t>(1, (n + most - 1) / most);
        for (std::int64_t i = 0; i < n; i += step) at.push_back(double(i));
        if (at.back() != double(n - 1)) at.push_back(double(n - 1));
        return at;
    };
    const std::vector<double> edgeColumns = along(width, 8192), edgeRows = along(height, 8192);
    const double lastColumn = double(width - 1), lastRow = double(height - 1);
    for (const double c : edgeColumns) {  // north edge, west to east
        cols.push_back(c);
        rows.push_back(0.0);
    }
    for (const double r : edgeRows) {  // east edge, north to south
        cols.push_back(lastColumn);
        rows.push_back(r);
    }
    for (auto c = edgeColumns.rbegin(); c != edgeColumns.rend(); ++c) {  // south, east to west
        cols.push_back(*c);
        rows.push_back(lastRow);
    }
    for (auto r = edgeRows.rbegin(); r != edgeRows.rend(); ++r) {  // west, south to north
        cols.push_back(0.0);
        rows.push_back(*r);
    }
    const std::size_t edgePoints = cols.size();
    for (int j = 0; j <= 32; ++j)
        for (int i = 0; i <= 32; ++i) {
            const double c = std::floor(double(width - 1) * i / 32.0);
            const double r = std::floor(double(height - 1) * j / 32.0);
            // The sample, its east neighbour and its south one (west and north at the end).
            const double east = c + 1 < double(width) ? c + 1 : c - 1;
            const double south = r + 1 < double(height) ? r + 1 : r - 1;
            cols.insert(cols.end(), {c, east, c});
            rows.insert(rows.end(), {r, r, south});
        }
    std::vector<double> lon, lat;
    if (!placer.place(cols, rows, lon, lat))
        return Error{fmt::format(
            "{}: some of its samples cannot be transformed to longitude and latitude on WGS84 "
            "(outside the projection's domain)",
            path)};
    // The footprint goes round a pole when its outline winds once round the axis: its
    // longitudes, step by step along the outline, add up to ±360°, not 0.
    double winding = 0.0;
    for (std::size_t k = 0; k < edgePoints; ++k)
        winding += std::remainder(lon[(k + 1) % edgePoints] - lon[k], 360.0);
    const bool aroundAPole = std::abs(winding) > 180.0;
    // Longitudes unwrapped around the first sample's, so a footprint across ±180° is one
    // interval.
    for (double& l : lon) l = lon.front() + std::remainder(l - lon.front(), 360.0);
    const auto [minLon, maxLon] = std::minmax_element(lon.begin(), lon.end());
    const auto [minLat, maxLat] = std::minmax_element(lat.begin(), lat.end());

    // The finest ground distance between neighbouring samples, from the local metric.
    double spacing = INFINITY;
    constexpr double kRadians = std::numbers::pi / 180.0;
    for (std::size_t k = edgePoints; k + 2 < lon.size(); k += 3) {
        const terrain::globe::CurvatureRadii radii = radiiAt(lat[k]);
        const double cosLat = std::cos(lat[k] * kRadians);
        for (const std::size_t n : {k + 1, k + 2}) {
            const double north = (lat[n] - lat[k]) * kRadians * radii.meridian;
            const double east = std::remainder(lon[n] - lon[k], 360.0) * kRadians *
                                radii.primeVertical * cosLat;
            const double d = std::hypot(north, east);
            if (d > 0.0) spacing = std::min(spacing, d);
        }
    }
    if (!std::isfinite(spacing))
        return Error{
            fmt::format("{}: its samples do not move on the ground from one to the next", path)};
    // Degrees of latitude shrink in metres towards the equator and degrees of longitude
    // towards the poles: the finest of each over the footprint.
    const double nearestLat =
        *minLat <= 0.0 && *maxLat >= 0.0 ? 0.0 : std::min(std::abs(*minLat), std::abs(*maxLat));
    const double pixelLon =
        spacing / (radiiAt(nearestLat).primeVertical * std::cos(nearestLat * kRadians)) / kRadians;
    const auto latitudeSpacing = [&](double farthestLat) {
        return spacing / radiiAt(farthestLat).meridian / kRadians;
    };

    // The grid round the footprint's own extremes; the one round a pole instead where that
    // one would reach past the pole, or span more than a hemisphere of longitude.
    GeographicTarget t;
    t.pixelLat = latitudeSpacing(std::max(std::abs(*minLat), std::abs(*maxLat)));
    t.pixelLon = pixelLon;
    double columns = std::ceil((*maxLon - *minLon) / t.pixelLon - 1e-9) + 1.0;
    double rowCount = std::ceil((*maxLat - *minLat) / t.pixelLat - 1e-9) + 1.0;
    t.west = *minLon - t.pixelLon / 2.0;
    t.north = *maxLat + t.pixelLat / 2.0;
    const bool reachesAPole = t.north > 90.0 || t.north - rowCount * t.pixelLat < -90.0;
    const bool wide = *maxLon - *minLon > 180.0;
    Pole pole = Pole::None;
    if (aroundAPole)
        pole = *maxLat > -*minLat ? Pole::North : Pole::South;
    else if (reachesAPole || wide)
        pole = *minLat > 0.0 ? Pole::North : *maxLat < 0.0 ? Pole::South : Pole::None;
    if (pole != Pole::None) {
        // Every longitude, the columns a whole number over 360°; the rows from the pole (the
        // grid's edge there) to the sample centre farthest from it, a whole number too.
        const double pixelLat = latitudeSpacing(90.0);
        columns = std::ceil(360.0 / pixelLon - 1e-9);
        t.pixelLon = 360.0 / columns;
        t.west = -180.0;
        const double fromPole = pole == Pole::North ? 90.0 - *minLat : *maxLat + 90.0;
        rowCount = std::ceil(fromPole / pixelLat + 0.5 - 1e-9);
        t.pixelLat = fromPole / (rowCount - 0.5);
        t.north = pole == Pole::North ? 90.0 : *maxLat + t.pixelLat / 2.0;
    } else if (wide || reachesAPole) {
        return Error{fmt::format(
            "{}: its samples span {:.1f}° of longitude and latitudes {:.4f}° to {:.4f}°, on "
            "both sides of the equator, without going round a pole: they cannot go onto one "
            "longitude/latitude grid; cut it into parts first (gdalwarp -te)",
            path, *maxLon - *minLon, *minLat, *maxLat)};
    } else if (t.west < -180.0) {
        // Across the antimeridian: the grid starts west of it and runs on past 180°.
        t.west += 360.0;
    }
    // A UTM zone's grid turns by up to a few degrees against the meridians; a footprint
    // that needs far more samples than the source has is not one a DEM's grid makes.
    constexpr double kMostSamplesPerSource = 64.0;
    if (!(columns >= 1.0 && rowCount >= 1.0 && columns <= INT_MAX && rowCount <= INT_MAX &&
          columns * rowCount <= kMostSamplesPerSource * double(width) * double(height)))
        return Error{fmt::format(
            "{}: on a longitude/latitude grid{} its {} × {} samples would need {} × {}, over {} "
            "times as many",
            path, pole == Pole::None ? "" : " round the pole", width, height, columns, rowCount,
            kMostSamplesPerSource)};
    t.width = static_cast<std::int64_t>(columns);
    t.height = static_cast<std::int64_t>(rowCount);
    return t;
}

// The warped grid, and the source's own samples with their places on it.
class GeographicGdalDemReader final : public DemReader {
public:
    GeographicGdalDemReader(DemInfo info, std::unique_ptr<GdalDemReader> original,
                            WarpedDataset warped, std::unique_ptr<GdalDemReader> resampled,
                            SamplePlacer placer, GeographicTarget target)
        : m_info(std::move(info)),
          m_original(std::move(original)),
          m_warped(std::move(warped)),
          m_resampled(std::move(resampled)),
          m_placer(std::move(placer)),
          m_target(target) {}

    const DemInfo& info() const override { return m_info; }
    Status readWindow(std::int64_t x0, std::int64_t y0, std::int64_t width, std::int64_t rows,
                      std::span<float> out) override {
        return m_resampled->readWindow(x0, y0, width, rows, out);
    }
    DemReader* originalSamples() override { return m_original.get(); }
    Status placeOriginalSamples(std::int64_t firstColumn, std::int64_t row, std::span<double> x,
                                std::span<double> y) override {
        m_columns.resize(x.size());
        m_rows.assign(x.size(), double(row));
        for (std::size_t i = 0; i < x.size(); ++i) m_columns[i] = double(firstColumn) + double(i);
        if (!m_placer.place(m_columns, m_rows, m_lon, m_lat))
            return Error{fmt::format(
                "{}: a sample of row {} cannot be transformed to longitude and latitude",
                m_info.path, row)};
        for (std::size_t i = 0; i < x.size(); ++i) {
            // Unwrapped onto the grid's own span of longitudes.
            const double lon =
                m_target.west + 180.0 + std::remainder(m_lon[i] - m_target.west - 180.0, 360.0);
            x[i] = (lon - m_target.west) / m_target.pixelLon - 0.5;
            y[i] = (m_target.north - m_lat[i]) / m_target.pixelLat - 0.5;
        }
        return {};
    }

private:
    DemInfo m_info;
    std::unique_ptr<GdalDemReader> m_original;
    WarpedDataset m_warped;
    std::unique_ptr<GdalDemReader> m_resampled;  // reads m_warped's dataset: closes first
    SamplePlacer m_placer;
    GeographicTarget m_target;
    std::vector<double> m_columns, m_rows, m_lon, m_lat;
};

}  // namespace

DemReaderResult openGeographicGdalDem(const std::string& path, const DemOpenOptions& options) {
    if (options.pixelSize || options.originX || options.originY)
        return Error{fmt::format(
            "{}: a projected source goes onto the globe where its own geotransform places it; "
            "--spacing and --origin cannot be given for it",
            path)};
    Result<GdalDataset> opened = openGdalDataset(path, options.maxDecodeBytes);
    if (!opened) return opened.error();
    GdalDataset dataset = std::move(opened).value();
    Result<DemInfo> described =
        describeGdalDataset(*dataset, path, options.band, RotatedGrids::Resample);
    if (!described) return described.error();
    DemInfo own = std::move(described).value();
    // The source's stored grid: a rotated one as stored, a north-up one as read (flipped
    // rows and columns already turned north-up and west-first).
    std::array<double, 6> gt{};
    if (own.resampledFrom) {
        gt = own.resampledFrom->geoTransform;
        own.width = own.resampledFrom->width;
        own.height = own.resampledFrom->height;
    } else if (own.hasGeoreference) {
        const Georeference& g = own.georeference;
        gt = {g.originX, g.pixelSizeX, 0.0, g.originY, 0.0, -g.pixelSizeY};
    } else {
        return Error{
            fmt::format("{}: it has no geotransform, so it cannot be placed on the globe", path)};
    }
    if (Status s = applyDemOpenOptions(own, options); !s) return s.error();
    if (own.width < 2 || own.height < 2)
        return Error{fmt::format(
            "{}: a grid of {} × {} samples is too small to resample onto the globe (2 × 2 at "
            "least)",
            path, own.width, own.height)};

    GdalErrorCapture errors;
    OGRSpatialReference sourceCrs;
    const bool known =
        options.epsg ? sourceCrs.importFromEPSG(*options.epsg) == OGRERR_NONE
                     : !own.georeference.wkt.empty() &&
                           sourceCrs.importFromWkt(own.georeference.wkt.c_str()) == OGRERR_NONE;
    if (!known)
        return Error{fmt::format(
            "{}: its CRS is not known, so it cannot be placed on the globe; give --epsg", path)};
    sourceCrs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    OGRSpatialReference wgs84;
    wgs84.importFromEPSG(Georeference::kWgs84Geographic);
    wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    CoordinateTransform toWgs84(OGRCreateCoordinateTransformation(&sourceCrs, &wgs84));
    if (!toWgs84)
        return Error{fmt::format("{}: PROJ cannot transform its CRS to WGS84: {}", path,
                                 errors.message("no transformation"))};
    SamplePlacer placer(gt, std::move(toWgs84));
    Result<GeographicTarget> made = targetFor(path, placer, own.width, own.height);
    if (!made) return made.error();
    const GeographicTarget& target = made.value();

    DemInfo info = own;
    info.resampledFrom = ResampledGrid{own.width, own.height, gt, {}, "bilinear", wktOf(sourceCrs)};
    info.width = target.width;
    info.height = target.height;
    info.hasGeoreference = true;
    info.rowsFlipped = info.columnsFlipped = false;
    Georeference& geo = info.georeference;
    geo = Georeference{};
    geo.crsKind = CrsKind::Geographic;
    geo.epsg = Georeference::kWgs84Geographic;
    geo.wkt = wktOf(wgs84);
    geo.originX = target.west;
    geo.originY = target.north;
    geo.pixelSizeX = target.pixelLon;
    geo.pixelSizeY = target.pixelLat;
    info.warnings.push_back(fmt::format(
        "{}: {} grid of {} × {} samples resampled {} by GDAL's warper onto a longitude/latitude "
        "grid on WGS84 of {} × {} at {:.3g}″ × {:.3g}″; the error bounds cover the source's own "
        "samples",
        path, crsLabel(sourceCrs), own.width, own.height, info.resampledFrom->method, target.width,
        target.height, target.pixelLon * 3600.0, target.pixelLat * 3600.0));

    // The source's own samples: stored rows and columns (flipped north-up), no placement.
    own.hasGeoreference = false;
    own.georeference = Georeference{};
    own.georeference.crsKind = CrsKind::Unknown;
    own.warnings.clear();
    own.resampledFrom.reset();
    // A rotated grid is read as stored; describeGdalDataset flips only north-up ones.
    GDALDataset& source = *dataset;
    const bool wide = isWideSampleType(source.GetRasterBand(info.band)->GetRasterDataType());
    auto original = std::make_unique<GdalDemReader>(own, std::move(dataset));
    Result<WarpedDataset> warped = warpBilinear(
        source, info,
        {.west = target.west,
         .south = target.north - double(target.height) * target.pixelLat,
         .east = target.west + double(target.width) * target.pixelLon,
         .north = target.north,
         .width = target.width,
         .height = target.height,
         .targetCrs = "EPSG:4326",
         .sourceCrs = options.epsg ? fmt::format("EPSG:{}", *options.epsg) : std::string{}},
        wide, "a longitude/latitude grid");
    if (!warped) return warped.error();
    // The warper's output must be the grid asked for, longitude first.
    std::array<double, 6> got{};
    warped.value().warped->GetGeoTransform(got.data());
    if (std::abs(got[0] - target.west) > 1e-9 * std::max(1.0, std::abs(target.west)) ||
        std::abs(got[3] - target.north) > 1e-9 * std::max(1.0, std::abs(target.north)) ||
        got[2] != 0.0 || got[4] != 0.0)
        return Error{fmt::format(
            "{}: GDAL's warper made the grid ({}, {}, {}, {}, {}, {}) instead of the one asked for",
            path, got[0], got[1], got[2], got[3], got[4], got[5])};
    // The warper marks samples outside the source NaN and reads around no-data; its raw
    // values are interpolated, so none of them is the source's no-data value.
    DemInfo resampledInfo = info;
    resampledInfo.noDataValue.reset();
    GDALDataset* warpedDataset = warped.value().warped.release();
    auto resampled = std::make_unique<GdalDemReader>(
        std::move(resampledInfo), GdalDataset(warpedDataset), std::vector<PixelRect>{}, 1);
    return std::unique_ptr<DemReader>(std::make_unique<GeographicGdalDemReader>(
        std::move(info), std::move(original), std::move(warped).value(), std::move(resampled),
        std::move(placer), target));
}

}  // namespace terrain::io::detail
