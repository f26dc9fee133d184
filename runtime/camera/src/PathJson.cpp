// PathJson: the camera path formats, and the files' reading, checking and atomic writing.
#include "PathJson.h"

#include "terrain/base/AtomicFile.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <system_error>
#include <vector>

namespace terrain::runtime::path_json {
namespace {

constexpr std::array<std::string_view, 5> kTopKeys = {"format", "version", "description", "units",
                                                      "keyframes"};

constexpr std::array<std::pair<std::string_view, std::string_view>, 3> kPlanarUnits = {{
    {"position",
     "metres, world frame of the pyramid: x east, y north, z up; a projected pyramid's own "
     "map coordinates (easting, northing of sample centres)"},
    {"angles", "degrees; yaw 0 looks north (+y), 90 east (+x); pitch positive looks up"},
    {"time", "seconds"},
}};
constexpr std::array<std::string_view, 6> kPlanarKeyframeKeys = {
    "time_s", "position_m", "look_at_m", "yaw_deg", "pitch_deg", "fov_y_deg"};

constexpr std::array<std::pair<std::string_view, std::string_view>, 4> kGlobeUnits = {{
    {"position", "latitude and longitude in degrees on WGS84"},
    {"height", "metres above the WGS84 ellipsoid"},
    {"angles", "degrees; heading 0 looks north, 90 east; pitch 0 at the horizon, -90 down"},
    {"time", "seconds"},
}};
constexpr std::array<std::string_view, 7> kGlobeKeyframeKeys = {
    "time_s", "latitude_deg", "longitude_deg", "height_m", "heading_deg", "pitch_deg", "fov_y_deg"};

const PathFormat kPlanarFormat{
    .name = "terrain-camera-path",
    .version = 1,
    .title = "camera path",
    .units = kPlanarUnits,
    .keyframeKeys = kPlanarKeyframeKeys,
    .forOtherSurface =
        "a planar camera path (\"terrain-camera-path\", positions in metres); a globe pyramid "
        "flies a \"terrain-globe-camera-path\" in latitude, longitude and height "
        "(docs/camera-path.md, \"Globe camera paths\")"};

const PathFormat kGlobeFormat{
    .name = "terrain-globe-camera-path",
    .version = 1,
    .title = "globe camera path",
    .units = kGlobeUnits,
    .keyframeKeys = kGlobeKeyframeKeys,
    .forOtherSurface =
        "a globe camera path (\"terrain-globe-camera-path\", latitude, longitude and height); a "
        "planar pyramid flies a \"terrain-camera-path\" in its own metres (docs/camera-path.md)"};

}  // namespace

const PathFormat& pathFormat(PathFrame frame) {
    return frame == PathFrame::Globe ? kGlobeFormat : kPlanarFormat;
}

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

Status writeFile(const std::filesystem::path& path, const PathFormat& format,
                 std::span<const Json> keyframes) {
    Json units = Json::object();
    for (const auto& [key, text] : format.units) units[std::string(key)] = std::string(text);
    std::string text = fmt::format(
        "{{\n  \"format\": \"{}\",\n  \"version\": {},\n  \"units\": {},\n  \"keyframes\": [\n",
        format.name, format.version, units.dump());
    for (std::size_t i = 0; i < keyframes.size(); ++i) {
        text += "    " + keyframes[i].dump();
        text += i + 1 < keyframes.size() ? ",\n" : "\n";
    }
    text += "  ]\n}\n";
    return writeTextAtomically(path, text);
}

const Json& checkedKeyframes(const Json& root, const PathFormat& format) {
    if (!root.is_object()) throw FileProblem{"not a camera path: the JSON is not an object"};
    const auto formatIt = root.find("format");
    if (!formatIs(root, format.name))
        throw FileProblem{
            fmt::format("not a {}: \"format\" must be \"{}\"{}", format.title, format.name,
                        formatIt == root.end() ? " (it is missing)" : ", not " + formatIt->dump())};
    const int version = format.version;
    const auto versionIt = root.find("version");
    if (versionIt == root.end() || !versionIt->is_number_integer() ||
        versionIt->get<std::int64_t>() != version)
        throw FileProblem{fmt::format(
            "unsupported \"version\" {} (this program reads version {})",
            versionIt == root.end() ? std::string("(missing)") : versionIt->dump(), version)};
    rejectUnknownKeys(root, kTopKeys, "");
    if (const auto description = root.find("description");
        description != root.end() && !description->is_string())
        throw FileProblem{"\"description\" must be a string"};
    if (const auto units = root.find("units"); units != root.end()) {
        if (!units->is_object()) throw FileProblem{"\"units\" must be an object"};
        std::vector<std::string_view> unitKeys;
        for (const auto& unit : format.units) unitKeys.push_back(unit.first);
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

std::string checkedKeyframe(const Json& keyframe, std::size_t index) {
    std::string where = fmt::format("keyframes[{}]: ", index);
    if (!keyframe.is_object())
        throw FileProblem{
            fmt::format("{}a keyframe must be an object, not {}", where, keyframe.dump())};
    return where;
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
