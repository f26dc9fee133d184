// DemOpenOptions applied to a DemInfo: what the command line says wins over the file.
#include "terrain/dem/OpenDem.h"
#include "DemReaderFactories.h"
#include "GdalSession.h"

#include <fmt/format.h>
#include <ogr_spatialref.h>

#include <cmath>

namespace terrain::io::detail {

namespace {

// The kind and WKT of an EPSG code from PROJ's database.
Status describeEpsg(const std::string& path, int epsg, Georeference& geo) {
    GdalErrorCapture errors;
    OGRSpatialReference srs;
    if (epsg <= 0 || srs.importFromEPSG(epsg) != OGRERR_NONE)
        return Error{fmt::format("{}: EPSG:{} is not a CRS that PROJ knows ({})", path, epsg,
                                 errors.message("no such code"))};
    geo.epsg = epsg;
    geo.crsKind = srs.IsGeographic()  ? CrsKind::Geographic
                  : srs.IsProjected() ? CrsKind::Projected
                                      : CrsKind::Unknown;
    geo.wkt = wktOf(srs);
    return {};
}

// What a user of GDAL or Cesium expects of a file that does not say everything: a grid
// spacing (geotransform, coordinate variables, ModelPixelScale) without a CRS is that
// spacing in metres, as gdalinfo shows it; only a file with no spacing at all is 1 m per
// sample. Either way the user is told, with the flags that say otherwise.
void assumeMissingGeoreference(DemInfo& info) {
    Georeference& geo = info.georeference;
    if (!info.hasGeoreference) {
        info.warnings.push_back(fmt::format(
            "{}: the file gives no sample spacing and no CRS; built at 1 m per sample with "
            "heights in metres. Give --spacing METRES (and --epsg CODE, --origin X,Y) if "
            "that is wrong",
            info.path));
        return;
    }
    if (geo.crsKind != CrsKind::Unknown) return;
    geo.crsKind = CrsKind::Projected;
    geo.epsg = Georeference::kUnknownProjectedCrs;
    // Degrees look like this: a spacing well under a unit, the grid inside ±180 × ±90.
    const double east = geo.originX + geo.pixelSizeX * static_cast<double>(info.width);
    const double south = geo.originY - geo.pixelSizeY * static_cast<double>(info.height);
    const bool looksLikeDegrees = geo.pixelSizeX < 0.1 && geo.pixelSizeY < 0.1 &&
                                  geo.originX >= -180.0 && east <= 360.0 && geo.originY <= 90.0 &&
                                  south >= -90.0;
    info.warnings.push_back(fmt::format(
        "{}: the CRS is unknown; the file's grid spacing {:g} × {:g} is taken as metres (an "
        "unnamed projected CRS). {}",
        info.path, geo.pixelSizeX, geo.pixelSizeY,
        looksLikeDegrees ? "That spacing looks like degrees: give --epsg 4326 if it is"
                         : "Give --epsg CODE if the map units are not metres"));
}

// A longitude/latitude grid placed by the flags must lie on the globe: --spacing and --origin
// are in degrees there, so an SRTM tile given --spacing 1 (meant as metres) would reach
// latitude −1154° and every later step would meet a NaN. Half a sample beyond ±90° is a
// global grid whose samples are centred on the poles (pixel-is-area edges), so one sample of
// slack; across longitudes, 360° and one sample.
Status checkGeographicPlacement(const DemInfo& info) {
    const Georeference& geo = info.georeference;
    if (geo.crsKind != CrsKind::Geographic) return {};
    const double north = geo.originY;
    const double south = geo.originY - geo.pixelSizeY * static_cast<double>(info.height);
    const double span = geo.pixelSizeX * static_cast<double>(info.width);
    if (north <= 90.0 + geo.pixelSizeY && south >= -90.0 - geo.pixelSizeY &&
        span <= 360.0 + geo.pixelSizeX)
        return {};
    return Error{fmt::format(
        "{}: placed by --spacing/--origin on a longitude/latitude CRS (EPSG:{}), its {} × {} "
        "samples {:g}° × {:g}° apart span latitudes {:g}° to {:g}° and {:g}° of longitude, "
        "beyond the globe (±90°, 360°): a geographic grid's spacing and origin are degrees; "
        "give --epsg CODE of a projected CRS for metres",
        info.path, geo.epsg, info.width, info.height, geo.pixelSizeX, geo.pixelSizeY, north,
        south, span)};
}

}  // namespace

Status applyDemOpenOptions(DemInfo& info, const DemOpenOptions& options) {
    if (options.verticalScale) {
        if (!std::isfinite(*options.verticalScale) || *options.verticalScale == 0.0)
            return Error{fmt::format("{}: vertical scale {} is not a finite non-zero number",
                                     info.path, *options.verticalScale)};
        info.vertical.scale = *options.verticalScale;
    }
    if (options.verticalOffset) {
        if (!std::isfinite(*options.verticalOffset))
            return Error{fmt::format("{}: vertical offset {} is not finite", info.path,
                                     *options.verticalOffset)};
        info.vertical.offset = *options.verticalOffset;
    }
    if (options.noDataValue) info.noDataValue = *options.noDataValue;

    const bool placed = options.pixelSize || options.originX || options.originY || options.epsg;
    if (!placed) {
        assumeMissingGeoreference(info);
        return {};
    }
    Georeference& geo = info.georeference;
    if (options.pixelSize) {
        if (!(*options.pixelSize > 0.0) || !std::isfinite(*options.pixelSize))
            return Error{fmt::format("{}: pixel size {} is not a positive number", info.path,
                                     *options.pixelSize)};
        geo.pixelSizeX = geo.pixelSizeY = *options.pixelSize;
    }
    if (options.originX) geo.originX = *options.originX;
    if (options.originY) geo.originY = *options.originY;
    if (options.epsg) {
        if (Status s = describeEpsg(info.path, *options.epsg, geo); !s) return s;
    } else if (geo.crsKind == CrsKind::Unknown) {
        // A placement given for a raster without a CRS: map units are metres in an unnamed
        // projected CRS, the convention of the GeoTIFF writer.
        geo.crsKind = CrsKind::Projected;
        geo.epsg = Georeference::kUnknownProjectedCrs;
    }
    info.hasGeoreference = true;
    return checkGeographicPlacement(info);
}

}  // namespace terrain::io::detail
