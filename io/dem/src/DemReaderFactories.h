// The DEM readers behind openDem (OpenDem.cpp), one factory per kind of source, plus the
// checks every reader shares. Each factory applies the DemOpenOptions to the DemInfo it
// builds, so its reader converts samples with the final vertical transform and no-data.
#pragma once

#include "terrain/dem/OpenDem.h"
#include "terrain/source/DemReader.h"

#include <cctype>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace terrain::io::detail {

using DemReaderResult = Result<std::unique_ptr<DemReader>>;

/// GeoTIFF/TIFF, PNG, OpenEXR, JPEG through OpenImageIO (OiioDemReader.cpp).
DemReaderResult openOiioDem(const std::string& path, const DemOpenOptions& options);
/// A raw SRTM .hgt tile (HgtDemReader.cpp).
DemReaderResult openHgtDem(const std::string& path, const DemOpenOptions& options);
/// Anything GDAL opens (GdalDemReader.cpp).
DemReaderResult openGdalDem(const std::string& path, const DemOpenOptions& options);
/// Several GDAL inputs as one raster through an in-memory VRT (GdalDemMosaic.cpp).
DemReaderResult openGdalMosaic(const std::vector<std::string>& paths,
                               const DemOpenOptions& options);
/// A regular, non-empty file; else an Error "<path>: no such file" / "<path>: empty
/// file (0 bytes)" / … Returns its size in bytes.
Result<std::uint64_t> checkDemInputFile(const std::string& path);

/// Applies the overrides of `options` to `info` (georeference, vertical transform,
/// no-data). An EPSG code PROJ does not know is an Error naming info.path.
Status applyDemOpenOptions(DemInfo& info, const DemOpenOptions& options);

/// The extension of path in lower case, with its dot: ".tif".
inline std::string lowerExtension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

/// A library's message made to follow "<path>: ": one line ("; " between lines), without
/// a leading copy of the path (libtiff and OpenImageIO often start with it).
inline std::string libraryMessage(std::string message, const std::string& path) {
    while (!message.empty() && (message.back() == '\n' || message.back() == ' '))
        message.pop_back();
    for (std::size_t at = 0; (at = message.find('\n', at)) != std::string::npos;)
        message.replace(at, 1, "; ");
    for (const std::string& prefix : {path + ": ", "\"" + path + "\": ", "`" + path + "': "})
        if (message.starts_with(prefix)) message.erase(0, prefix.size());
    return message;
}

}  // namespace terrain::io::detail
