#include "DemInputList.h"

#include "terrain/dem/OpenDem.h"
#include "terrain/source/DemReader.h"

#include <fmt/format.h>
#include <glob.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <filesystem>
#include <string_view>
#include <system_error>

namespace terrain::io::detail {
namespace {

namespace fs = std::filesystem;

constexpr std::array<std::string_view, 14> kDemExtensions = {
    ".hgt", ".tif", ".tiff", ".dt0", ".dt1", ".dt2", ".nc",
    ".img", ".asc", ".bil",  ".vrt", ".png", ".exr", ".flt"};

bool isPattern(const std::string& input) { return input.find_first_of("*?[") != std::string::npos; }

Result<std::vector<std::string>> folderFiles(const std::string& folder) {
    std::vector<std::string> files;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(folder, ec)) {
        if (!entry.is_regular_file(ec)) continue;
        const std::string name = entry.path().filename().string();
        if (!name.starts_with(".") && hasDemExtension(name)) files.push_back(entry.path().string());
    }
    if (ec) return Error{fmt::format("{}: cannot list the folder: {}", folder, ec.message())};
    if (files.empty())
        return Error{
            fmt::format("{}: a folder without DEM files (.hgt, .tif, .tiff, .dt0–.dt2, "
                        ".nc, .img, .asc, .bil, .flt, .vrt, .png, .exr)",
                        folder)};
    std::sort(files.begin(), files.end());
    return files;
}

Result<std::vector<std::string>> patternFiles(const std::string& pattern) {
    glob_t matches{};
    const int status = glob(pattern.c_str(), GLOB_ERR, nullptr, &matches);
    std::vector<std::string> files;
    for (std::size_t i = 0; i < matches.gl_pathc; ++i) {
        std::error_code ec;
        if (fs::is_regular_file(matches.gl_pathv[i], ec)) files.emplace_back(matches.gl_pathv[i]);
    }
    globfree(&matches);
    if (status != 0 && status != GLOB_NOMATCH)
        return Error{fmt::format("{}: cannot list the files it names", pattern)};
    if (files.empty()) return Error{fmt::format("{}: matches no file", pattern)};
    return files;  // glob sorts them
}

}  // namespace

bool hasDemExtension(const std::string& path) {
    std::string extension = fs::path(path).extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return std::find(kDemExtensions.begin(), kDemExtensions.end(), extension) !=
           kDemExtensions.end();
}

Result<std::vector<std::string>> expandDemInputs(const std::vector<std::string>& inputs) {
    std::vector<std::string> expanded;
    for (const std::string& input : inputs) {
        std::error_code ec;
        Result<std::vector<std::string>> files = std::vector<std::string>{input};
        if (fs::is_directory(input, ec))
            files = folderFiles(input);
        else if (isPattern(input) && !fs::exists(input, ec) && !isGdalDatasetName(input) &&
                 !input.starts_with("procedural:"))
            files = patternFiles(input);
        if (!files) return files.error();
        expanded.insert(expanded.end(), files.value().begin(), files.value().end());
    }
    return expanded;
}

}  // namespace terrain::io::detail
