// PathJson: reading and writing the camera path files (docs/camera-path.md), shared by the
// planar and the globe path: the file read and parsed with its errors named, keys checked
// (a problem is thrown as FileProblem and prefixed with the path by the caller), and the
// file written one keyframe per line, atomically. Internal to terrain::camera.
#pragma once

#include "terrain/base/Result.h"

#include <nlohmann/json.hpp>

#include <array>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>

namespace terrain::runtime::path_json {

using Json = nlohmann::ordered_json;

struct FileProblem {
    std::string message;
};

/// The file's JSON; errors name the file: missing, a folder, unreadable, not JSON.
Result<Json> readFile(const std::filesystem::path& path);

/// Writes {"format", "version", "units", "keyframes"} with one compact keyframe per line (a
/// file people edit shows one keyframe per line), atomically.
Status writeFile(const std::filesystem::path& path, std::string_view format, int version,
                 const Json& units, std::span<const Json> keyframes);

/// Checks "format" and "version", rejects top-level keys outside `known`, checks
/// "description" and "units" (whose keys must be in `unitKeys`) and returns the "keyframes"
/// array; throws FileProblem.
const Json& checkedKeyframes(const Json& root, std::string_view format, int version,
                             std::span<const std::string_view> known,
                             std::span<const std::string_view> unitKeys);

/// Whether `root` is an object whose "format" is the string `format` (anything else, a
/// number included, is not: a fuzzed file put 999999999 there).
bool formatIs(const Json& root, std::string_view format);

/// Throws FileProblem naming the first key of `object` outside `known`.
void rejectUnknownKeys(const Json& object, std::span<const std::string_view> known,
                       const std::string& where);

/// The number at `key`; throws FileProblem if it is missing or not a number.
double numberAt(const Json& object, std::string_view key, const std::string& where);

}  // namespace terrain::runtime::path_json
