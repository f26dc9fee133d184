// layer.json of an imagery layer (ImageryLayerIndex.h), through nlohmann::json.
#include "terrain/pyramid/ImageryLayerIndex.h"
#include "terrain/remote/RemoteFiles.h"

#include "terrain/base/AtomicFile.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

namespace terrain::io {

std::int64_t ImageryLayerIndex::presentTiles() const {
    std::int64_t n = 0;
    for (const ImageryIndexLevel& l : levels)
        for (const ImageryIndexFile& f : l.files) n += f.presentTiles;
    return n;
}

std::int64_t ImageryLayerIndex::bytes() const {
    std::int64_t n = 0;
    for (const ImageryIndexLevel& l : levels)
        for (const ImageryIndexFile& f : l.files) n += f.bytes;
    return n;
}

Status writeImageryIndex(const std::filesystem::path& layerDir, const ImageryLayerIndex& index) {
    nlohmann::ordered_json j;
    j["format"] = ImageryLayerIndex::kFormatName;
    j["formatVersion"] = ImageryLayerIndex::kFormatVersion;
    j["codec"] = index.codec;
    j["lossless"] = index.lossless;
    j["quality"] = index.quality;
    j["levels"] = nlohmann::ordered_json::array();
    for (const ImageryIndexLevel& l : index.levels) {
        nlohmann::ordered_json level;
        level["level"] = l.level;
        level["files"] = nlohmann::ordered_json::array();
        for (const ImageryIndexFile& f : l.files)
            level["files"].push_back({f.x, f.y, f.presentTiles, f.bytes});
        j["levels"].push_back(std::move(level));
    }
    const std::string text = j.dump(1) + "\n";
    const std::filesystem::path path = layerDir / "layer.json";
    return writeTextAtomically(path, text);
}

Result<ImageryLayerIndex> readImageryIndex(const std::filesystem::path& layerDir) {
    Result<std::unique_ptr<remote::RemoteFiles>> files = remote::filesFor(layerDir.string());
    if (!files) return files.error();
    return readImageryIndex(layerDir, files.value().get());
}

Result<ImageryLayerIndex> readImageryIndex(const std::filesystem::path& layerDir,
                                           remote::RemoteFiles* files) {
    const std::filesystem::path path = layerDir / "layer.json";
    std::filesystem::path local = path;
    if (files != nullptr) {  // a pyramid at a URL (issue 49)
        Result<std::filesystem::path> copy = files->localCopy(path.string());
        if (!copy) return copy.error();
        local = std::move(copy).value();
    }
    std::ifstream in(local, std::ios::binary);
    if (!in.is_open())
        return Error{fmt::format("{}: cannot open: {}", path.string(), std::strerror(errno))};
    std::ostringstream text;
    text << in.rdbuf();
    const nlohmann::json j = nlohmann::json::parse(text.str(), nullptr, false);
    const auto bad = [&](std::string_view what) {
        return Error{fmt::format("{}: not an imagery layer index: {}", path.string(), what)};
    };
    if (j.is_discarded() || !j.is_object()) return bad("not JSON");
    try {
        if (j.at("format").get<std::string>() != ImageryLayerIndex::kFormatName)
            return bad("wrong format name");
        if (j.at("formatVersion").get<int>() != ImageryLayerIndex::kFormatVersion)
            return bad(fmt::format("format version {}; this reader reads {}",
                                   j.at("formatVersion").get<int>(),
                                   ImageryLayerIndex::kFormatVersion));
        ImageryLayerIndex index;
        index.codec = j.at("codec").get<std::string>();
        if (index.codec != "webp") return bad(fmt::format("unknown codec \"{}\"", index.codec));
        index.lossless = j.at("lossless").get<bool>();
        index.quality = j.at("quality").get<int>();
        for (const nlohmann::json& level : j.at("levels")) {
            ImageryIndexLevel l;
            l.level = level.at("level").get<int>();
            if (l.level < 0 || l.level > 64) return bad(fmt::format("level {}", l.level));
            for (const nlohmann::json& f : level.at("files")) {
                ImageryIndexFile file{f.at(0).get<std::int64_t>(), f.at(1).get<std::int64_t>(),
                                      f.at(2).get<std::int64_t>(), f.at(3).get<std::int64_t>()};
                if (file.x < 0 || file.y < 0 || file.presentTiles < 0 || file.bytes < 0)
                    return bad(fmt::format("level {}: a negative file entry", l.level));
                l.files.push_back(file);
            }
            index.levels.push_back(std::move(l));
        }
        return index;
    } catch (const nlohmann::json::exception& e) {
        return bad(e.what());
    }
}

}  // namespace terrain::io
