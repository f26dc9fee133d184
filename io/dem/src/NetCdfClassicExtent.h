// Where the data of a netCDF classic file (CDF-1, CDF-2 64-bit offset, CDF-5) must end,
// read from its header. The netCDF library reads a truncated classic file without
// complaint, filling the missing part with the fill value (so a cut download would read
// as a hole of no-data); comparing this extent with the file size catches it. The walk
// also refuses a header the file cannot hold before the netCDF library sees it: that
// library allocates what a header declares (an attribute of 3.6 GB in a 400-byte file,
// found by fuzz-dem-netcdf).
#pragma once

#include "terrain/base/Result.h"

#include <cstdint>
#include <optional>
#include <string>

namespace terrain::io::detail {

/// The byte offset just past the last variable's data; nullopt when `path` is not a
/// netCDF classic file, or its header is larger than the walk reads (the check is then
/// skipped; GDAL reports what it finds). An Error naming `path` when the header is corrupt:
/// it runs past the end of the file, or holds an unknown tag, type or dimension.
Result<std::optional<std::uint64_t>> netCdfClassicDataEnd(const std::string& path);

}  // namespace terrain::io::detail
