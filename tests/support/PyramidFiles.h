// PyramidFiles: a pyramid folder's files by relative path, for tests that compare two builds
// byte for byte (region builds against whole or one-process builds); the manifest without
// build.seconds, which is the build's wall time.
#pragma once

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

namespace terrain::test {

inline std::string fileBytes(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream bytes;
    bytes << in.rdbuf();
    return bytes.str();
}

inline std::map<std::string, std::string> pyramidFiles(const std::filesystem::path& folder) {
    std::map<std::string, std::string> files;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(folder)) {
        if (!entry.is_regular_file()) continue;
        std::string bytes = fileBytes(entry.path());
        if (entry.path().filename() == "manifest.json") {
            auto manifest = nlohmann::json::parse(bytes);
            manifest["build"].erase("seconds");
            bytes = manifest.dump(1);
        }
        files[std::filesystem::relative(entry.path(), folder).string()] = std::move(bytes);
    }
    return files;
}

}  // namespace terrain::test
