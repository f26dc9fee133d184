// The shader files of shaders/, compiled into terrain::runtime at build time
// (cmake/EmbedShaders.cmake), so an installed runtime needs no shader folder.
#pragma once

#include <span>
#include <string_view>

namespace terrain::runtime {

struct EmbeddedShader {
    std::string_view name;    ///< file name within shaders/, e.g. "tess_test.vert"
    std::string_view source;  ///< the file's text, byte for byte
};

/// Every embedded file, sorted by name. Defined in the generated EmbeddedShaders.cpp.
std::span<const EmbeddedShader> embeddedShaders();

/// The embedded file called `name`, or null.
const EmbeddedShader* findEmbeddedShader(std::string_view name);

}  // namespace terrain::runtime
