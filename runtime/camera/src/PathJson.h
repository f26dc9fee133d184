// PathJson: reading and writing the camera path files (docs/camera-path.md), one reader for
// the planar and the globe path: each file format described as data (PathFormat: its name,
// version, units and keys, and why the other surface's pyramid refuses it), the file read
// and parsed with its errors named, the checks every format shares written once (a problem
// is thrown as FileProblem and prefixed with the file by FlightPath's reader), and the file
// written one keyframe per line, atomically. Internal to terrain::camera.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/runtime/CameraPath.h"
#include "terrain/runtime/FlightPath.h"
#include "terrain/runtime/GlobeCameraPath.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace terrain::runtime::path_json {

using Json = nlohmann::ordered_json;

struct FileProblem {
    std::string message;
};

/// One camera path file format, as data.
struct PathFormat {
    std::string_view name;   ///< the file's "format"
    int version = 1;         ///< the file's "version" this program reads and writes
    std::string_view title;  ///< "camera path", "globe camera path": what the errors call it
    /// What "units" may say, key and the text save() writes, in the order it writes them.
    std::span<const std::pair<std::string_view, std::string_view>> units;
    std::span<const std::string_view> keyframeKeys;  ///< every key a keyframe may have
    /// Why a pyramid of the other surface refuses a file of this format.
    std::string_view forOtherSurface;
};

const PathFormat& pathFormat(PathFrame frame);

/// The file's JSON; errors name the file: missing, a folder, unreadable, not JSON.
Result<Json> readFile(const std::filesystem::path& path);

/// Writes {"format", "version", "units", "keyframes"} of `format` with one compact keyframe
/// per line (a file people edit shows one keyframe per line), atomically.
Status writeFile(const std::filesystem::path& path, const PathFormat& format,
                 std::span<const Json> keyframes);

/// Checks "format" and "version", rejects unknown top-level keys, checks "description" and
/// "units" and returns the "keyframes" array; throws FileProblem.
const Json& checkedKeyframes(const Json& root, const PathFormat& format);

/// Whether `root` is an object whose "format" is the string `format` (anything else, a
/// number included, is not: a fuzzed file put 999999999 there).
bool formatIs(const Json& root, std::string_view format);

/// Throws FileProblem naming the first key of `object` outside `known`.
void rejectUnknownKeys(const Json& object, std::span<const std::string_view> known,
                       const std::string& where);

/// The number at `key`; throws FileProblem if it is missing or not a number.
double numberAt(const Json& object, std::string_view key, const std::string& where);

/// "keyframes[i]: " (what a keyframe's problems start with) after checking that the keyframe
/// is an object; throws FileProblem.
std::string checkedKeyframe(const Json& keyframe, std::size_t index);

// Each format's keyframes (CameraPath.cpp, GlobeCameraPath.cpp); throw FileProblem.
std::vector<CameraKeyframe> planarKeyframes(const Json& list);
std::vector<GlobeKeyframe> globeKeyframes(const Json& list);

}  // namespace terrain::runtime::path_json
