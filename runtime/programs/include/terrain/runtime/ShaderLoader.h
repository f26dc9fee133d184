// ShaderLoader: where shader text comes from: the embedded copy of shaders/, or a folder
// on disk (TERRAIN_SHADER_DIR) so a developer can edit shaders without rebuilding.
#pragma once

#include "terrain/base/Result.h"

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace terrain::runtime {

/// Environment variable naming a folder that replaces the embedded shaders.
inline constexpr const char* kShaderDirEnv = "TERRAIN_SHADER_DIR";

struct ShaderFile {
    std::string name;         ///< as asked for, e.g. "tess_test.vert"
    std::string displayName;  ///< what messages call it: the path on disk or the name
    std::string text;
};

class ShaderLoader {
public:
    /// Embedded shaders, or the folder named by TERRAIN_SHADER_DIR when that is set.
    static ShaderLoader fromEnvironment();

    /// Files from `directory`; std::nullopt: the embedded files.
    explicit ShaderLoader(std::optional<std::filesystem::path> directory = std::nullopt);

    /// Reads one file. Names are relative ("Bindings.h", "sub/x.glsl"); absolute names
    /// and ".." are errors. With a directory, a missing file is an error too (no silent
    /// fallback to the embedded copy, which would hide edits made in the wrong place).
    Result<ShaderFile> load(std::string_view name) const;

    const std::optional<std::filesystem::path>& directory() const { return m_directory; }

private:
    std::optional<std::filesystem::path> m_directory;
};

}  // namespace terrain::runtime
