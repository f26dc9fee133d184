// openDem: picks the reader for the inputs. "procedural:" is the built-in terrain,
// "planet:" the built-in planet (geographic), GDAL
// dataset names (subdatasets, /vsi… paths, inline VRT) GDAL, .hgt the SRTM reader, image
// extensions OpenImageIO (GDAL when a band is chosen), anything else (netCDF, VRT, DTED, ...)
// and every mosaic GDAL. A folder or a file pattern stands for the DEM files it names
// (DemInputList.h).
#include "terrain/dem/OpenDem.h"
#include "DemInputList.h"
#include "DemReaderFactories.h"
#include "GdalDemReader.h"
#include "terrain/source/ProceduralDems.h"

#include <fmt/format.h>

#include <array>
#include <cctype>
#include <filesystem>
#include <string_view>
#include <system_error>

namespace terrain::io {

namespace {

constexpr std::array<std::string_view, 7> kOiioExtensions = {".tif", ".tiff", ".png", ".exr",
                                                             ".jpg", ".jpeg", ".jpe"};

}  // namespace

bool isGdalDatasetName(const std::string& input) {
    if (input.starts_with("/vsi") || input.starts_with("<")) return true;
    // DRIVER:rest, the driver's short name two or more letters, digits or underscores (a
    // one-letter prefix would be a drive letter).
    const std::size_t colon = input.find(':');
    if (colon == std::string::npos || colon < 2) return false;
    for (std::size_t i = 0; i < colon; ++i) {
        const char c = input[i];
        if (!(std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_')) return false;
    }
    return !isProceduralDemName(input);
}

namespace {

// A source a globe cannot take as it is, but GDAL's warper can put onto a longitude/latitude
// grid: a projected one whose CRS is named, or a rotated geographic one.
bool needsGeographicGrid(const DemInfo& info) {
    const Georeference& g = info.georeference;
    if (g.crsKind == CrsKind::Geographic) return info.resampledFrom.has_value();
    return g.crsKind == CrsKind::Projected && (!g.wkt.empty() || g.epsg != 0);
}

Result<std::unique_ptr<DemReader>> openOne(const std::string& input, const DemOpenOptions& options);

}  // namespace

Result<std::unique_ptr<DemReader>> openDem(const std::vector<std::string>& given,
                                           const DemOpenOptions& options) {
    if (given.empty()) return Error{"openDem: no input given"};
    Result<std::vector<std::string>> expanded = detail::expandDemInputs(given);
    if (!expanded) return expanded.error();
    const std::vector<std::string>& inputs = expanded.value();
    if (inputs.size() > 1) {
        for (const std::string& input : inputs)
            if (isProceduralDemName(input))
                return Error{
                    fmt::format("{}: the procedural terrain cannot be part of a mosaic", input)};
        auto mosaic = detail::openGdalMosaic(inputs, options);
        if (mosaic && options.geographicGrid && needsGeographicGrid(mosaic.value()->info()))
            return Error{fmt::format(
                "{}: a mosaic of projected tiles cannot go onto the globe yet; make one "
                "raster of them first (gdalbuildvrt tiles.vrt …) and give that",
                inputs.front())};
        return mosaic;
    }
    const std::string& input = inputs.front();
    auto opened = openOne(input, options);
    if (opened && options.geographicGrid && !isProceduralDemName(input) &&
        needsGeographicGrid(opened.value()->info())) {
        opened.value().reset();  // the file is opened again, through GDAL
        return detail::openGeographicGdalDem(input, options);
    }
    return opened;
}

namespace {

Result<std::unique_ptr<DemReader>> openOne(const std::string& input,
                                           const DemOpenOptions& options) {
    if (isProceduralDemName(input)) {
        if (options.band && *options.band != 1)
            return Error{fmt::format("{}: the procedural terrain has one band, not band {}", input,
                                     *options.band)};
        return openProceduralDem(input, [&options](DemInfo& info) {
            return detail::applyDemOpenOptions(info, options);
        });
    }
    // A file whose name only looks like one (a ':' in a folder name) is a file.
    std::error_code error;
    if (isGdalDatasetName(input) && !std::filesystem::exists(input, error))
        return detail::openGdalDem(input, options);
    const std::string ext = detail::lowerExtension(input);
    if (ext == ".hgt") {
        if (options.band && *options.band != 1)
            return Error{fmt::format("{}: an SRTM .hgt tile has one band, not band {}", input,
                                     *options.band)};
        return detail::openHgtDem(input, options);
    }
    for (const std::string_view oiio : kOiioExtensions) {
        if (ext != oiio) continue;
        // GDAL numbers and chooses bands; OpenEXR's channels are not bands.
        if (options.band && ext == ".exr" && *options.band != 1)
            return Error{
                fmt::format("{}: OpenEXR heights are its first channel; there is no band {}", input,
                            *options.band)};
        if (options.band && ext != ".exr") return detail::openGdalDem(input, options);
        return detail::openOiioDem(input, options);
    }
    return detail::openGdalDem(input, options);
}

}  // namespace

}  // namespace terrain::io
