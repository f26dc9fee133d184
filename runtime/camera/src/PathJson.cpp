// PathJson: the camera path files' reading, checking and atomic writing.
#include "PathJson.h"

#include "terrain/base/AtomicFile.h"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <system_error>

namespace terrain::runtime::path_json {

Result<Json> readFile(const std::filesystem::path& path) {
    const std::string name = path.string();
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) return Error{name + ": no such file"};
    if (std::filesystem::is_directory(path, ec))
        return Error{name + ": is a folder, not a camera path file"};
    std::ifstream in(path, std::ios::binary);
    if (!in.is_open()) return Error{fmt::format("{}: cannot open: {}", name, std::strerror(errno))};
    std::ostringstream text;
    text << in.rdbuf();  // an empty file leaves text empty: a JSON parse error below
    if (in.bad()) return Error{name + ": cannot read the file"};
    try {
        return Json::parse(text.str());
    } catch (const Json::exception& e) {
        return Error{fmt::format("{}: not valid JSON: {}", name, e.what())};
    }
}

bool formatIs(const Json& root, std::string_view format) {
    if (!root.is_object()) return false;
    const auto found = root.find("format");
    return found != root.end() && found->is_string() && found->get<std::string>() == format;
}

Status writeFile(const std::filesystem::path& path, std::string_view format, int version,
                 const Json& units, std::span<const Json> keyframes) {
    std::string text = fmt::format(
        "{{\n  \"format\": \"{}\",\n  \"version\": {},\n  \"units\": {},\n  \"keyframes\": [\n",
        format, version, units.dump());
    for (std::size_t i = 0; i < keyframes.size(); ++i) {
        text += "    " + keyframes[i].dump();
        text += i + 1 < keyframes.size() ? ",\n" : "\n";
    }
    text += "  ]\n}\n";
    const std::string name = path.string();
    return writeAtomically(path, [&](const std::filesystem::path& temporary) -> Status {
        std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
        out.write(text.data(), static_cast<std::streamsize>(text.size()));
        out.close();
        if (!out) return Error{fmt::format("{}: cannot write: {}", name, std::strerror(errno))};
        return {};
    });
}

const Json& checkedKeyframes(const Json& root, std::string_view format, int version,
                             std::span<const std::string_view> known,
                             std::span<const std::string_view> unitKeys) {
    if (!root.is_object()) throw FileProblem{"not a camera path: the JSON is not an object"};
    const auto formatIt = root.find("format");
    if (formatIt == root.end() || !formatIt->is_string() || formatIt->get<std::string>() != format)
        throw FileProblem{fmt::format(
            "not a {}: \"format\" must be \"{}\"{}",
            format == "terrain-camera-path" ? "camera path" : "globe camera path", format,
            formatIt == root.end() ? " (it is missing)" : ", not " + formatIt->dump())};
    const auto versionIt = root.find("version");
    if (versionIt == root.end() || !versionIt->is_number_integer() ||
        versionIt->get<std::int64_t>() != version)
        throw FileProblem{fmt::format(
            "unsupported \"version\" {} (this program reads version {})",
            versionIt == root.end() ? std::string("(missing)") : versionIt->dump(), version)};
    rejectUnknownKeys(root, known, "");
    if (const auto description = root.find("description");
        description != root.end() && !description->is_string())
        throw FileProblem{"\"description\" must be a string"};
    if (const auto units = root.find("units"); units != root.end()) {
        if (!units->is_object()) throw FileProblem{"\"units\" must be an object"};
        rejectUnknownKeys(*units, unitKeys, "units: ");
        for (const auto& [key, value] : units->items())
            if (!value.is_string())
                throw FileProblem{fmt::format("units: \"{}\" must be a string", key)};
    }
    const auto list = root.find("keyframes");
    if (list == root.end()) throw FileProblem{"missing \"keyframes\" (an array of keyframes)"};
    if (!list->is_array()) throw FileProblem{"\"keyframes\" must be an array"};
    return *list;
}

void rejectUnknownKeys(const Json& object, std::span<const std::string_view> known,
                       const std::string& where) {
    for (const auto& [key, value] : object.items()) {
        if (std::find(known.begin(), known.end(), key) != known.end()) continue;
        std::string list;
        for (std::string_view k : known) list += fmt::format("{}{}", list.empty() ? "" : ", ", k);
        throw FileProblem{fmt::format("{}unknown key \"{}\" (known keys: {})", where, key, list)};
    }
}

double numberAt(const Json& object, std::string_view key, const std::string& where) {
    const auto it = object.find(key);
    if (it == object.end())
        throw FileProblem{fmt::format("{}missing \"{}\" (a number)", where, key)};
    if (!it->is_number())
        throw FileProblem{fmt::format("{}\"{}\" must be a number, not {}", where, key, it->dump())};
    return it->get<double>();
}

}  // namespace terrain::runtime::path_json
