// DemInputList: what the inputs of openDem name. A folder names the DEM files in it (by
// extension, sorted, not its subfolders); a pattern with * ? or [ that is not itself a file
// names the files it matches (glob(3), sorted), so a planet's thousands of SRTM tiles need
// not pass through the command line. Everything else names itself.
#pragma once

#include "terrain/base/Result.h"

#include <string>
#include <vector>

namespace terrain::io::detail {

/// The extensions a folder's DEM files have (lower case): .hgt, .tif, .tiff, .dt0–.dt2,
/// .nc, .img, .asc, .bil, .vrt, .png, .exr.
bool hasDemExtension(const std::string& path);

/// Expands folders and patterns; an Error names a folder without DEM files or a pattern
/// that matches none.
Result<std::vector<std::string>> expandDemInputs(const std::vector<std::string>& inputs);

}  // namespace terrain::io::detail
