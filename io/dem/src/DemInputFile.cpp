// The checks every file input passes before a reader sees it, so that a missing or empty
// file gets a plain message instead of a library's guess.
#include "DemReaderFactories.h"

#include <fmt/format.h>

#include <filesystem>
#include <system_error>

namespace terrain::io::detail {

Result<std::uint64_t> checkDemInputFile(const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code error;
    const fs::file_status status = fs::status(path, error);
    if (status.type() == fs::file_type::not_found)
        return Error{fmt::format("{}: no such file", path)};
    if (error) return Error{fmt::format("{}: cannot read: {}", path, error.message())};
    if (status.type() == fs::file_type::directory)
        return Error{fmt::format("{}: is a directory, not a DEM file", path)};
    if (status.type() != fs::file_type::regular)
        return Error{fmt::format("{}: not a regular file", path)};
    const std::uintmax_t size = fs::file_size(path, error);
    if (error) return Error{fmt::format("{}: cannot read: {}", path, error.message())};
    if (size == 0) return Error{fmt::format("{}: empty file (0 bytes)", path)};
    return static_cast<std::uint64_t>(size);
}

}  // namespace terrain::io::detail
