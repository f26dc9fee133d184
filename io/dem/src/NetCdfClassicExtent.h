// Where the data of a netCDF classic file (CDF-1, CDF-2 64-bit offset, CDF-5) must end,
// read from its header. The netCDF library reads a truncated classic file without
// complaint, filling the missing part with the fill value (so a cut download would read
// as a hole of no-data); comparing this extent with the file size catches it.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace terrain::io::detail {

/// The byte offset just past the last variable's data, or nullopt when `path` is not a
/// netCDF classic file or its header cannot be parsed (the check is then skipped; GDAL
/// reports what it finds).
std::optional<std::uint64_t> netCdfClassicDataEnd(const std::string& path);

}  // namespace terrain::io::detail
