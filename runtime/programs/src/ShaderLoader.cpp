// Shader text from the embedded table or from TERRAIN_SHADER_DIR.
#include "terrain/runtime/ShaderLoader.h"

#include "terrain/runtime/EmbeddedShaders.h"

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace terrain::runtime {

const EmbeddedShader* findEmbeddedShader(std::string_view name) {
    const auto shaders = embeddedShaders();
    const auto found = std::find_if(
        shaders.begin(), shaders.end(),
        [&](const EmbeddedShader& shader) { return !shader.name.empty() && shader.name == name; });
    return found != shaders.end() ? &*found : nullptr;
}

ShaderLoader ShaderLoader::fromEnvironment() {
    const char* directory = std::getenv(kShaderDirEnv);
    if (directory == nullptr || directory[0] == '\0') {
        return ShaderLoader();
    }
    return ShaderLoader(std::filesystem::path(directory));
}

ShaderLoader::ShaderLoader(std::optional<std::filesystem::path> directory)
    : m_directory(std::move(directory)) {}

Result<ShaderFile> ShaderLoader::load(std::string_view name) const {
    const std::filesystem::path relative(name);
    const bool escapes =
        std::any_of(relative.begin(), relative.end(),
                    [](const std::filesystem::path& part) { return part == ".."; });
    if (name.empty() || relative.is_absolute() || escapes) {
        return Error{"shader '" + std::string(name) +
                     "': names are relative to the shader folder, without '..'"};
    }

    if (!m_directory) {
        const EmbeddedShader* shader = findEmbeddedShader(name);
        if (shader == nullptr) {
            return Error{std::string(name) +
                         ": no such embedded shader (files of shaders/ "
                         "are embedded at build time)"};
        }
        return ShaderFile{std::string(name), std::string(name), std::string(shader->source)};
    }

    const std::filesystem::path path = *m_directory / relative;
    std::ifstream file(path, std::ios::binary);
    if (!file) {
        return Error{path.string() + ": cannot open shader (" + kShaderDirEnv +
                     " or the loader's folder points here)"};
    }
    std::ostringstream text;
    text << file.rdbuf();
    if (file.bad()) {
        return Error{path.string() + ": read error"};
    }
    return ShaderFile{std::string(name), path.string(), std::move(text).str()};
}

}  // namespace terrain::runtime
