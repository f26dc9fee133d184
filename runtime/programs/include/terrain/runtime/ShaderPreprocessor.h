// ShaderPreprocessor: turns one stage file into the text handed to the driver: the
// `#version 450 core` line, the caller's #defines, the file with `#include "Name"` lines
// inlined, and #line directives so the driver's messages carry original file lines.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/runtime/ShaderLoader.h"

#include <span>
#include <string>
#include <vector>

namespace terrain::runtime {

/// The GLSL version line every stage starts with.
inline constexpr std::string_view kGlslVersionLine = "#version 450 core";

/// File n of a stage (0 = the stage file, then its includes) is numbered from
/// n * kSourceLineStride + 1 in the #line directives, and is GLSL source string n. The line
/// number alone then names the file: Mesa reports source string 0 for errors found after
/// parsing (ShaderLog.cpp), so the source-string number cannot be relied on. The stage
/// file keeps its own line numbers.
inline constexpr unsigned long kSourceLineStride = 100000;

struct ShaderDefine {
    std::string name;   ///< an identifier
    std::string value;  ///< one line, may be empty
};

struct PreprocessedShader {
    std::string text;  ///< ready for glShaderSource
    /// The file behind each source number n (lines n * kSourceLineStride + ...): [0] is
    /// the stage file, then every included file in order of first inclusion.
    std::vector<std::string> sourceNames;
};

/// Preprocesses `root`. Includes are read through `loader` and inlined wherever they
/// appear (include guards work as in C); an include cycle, a missing include, a
/// `#version` line in a file, a file of kSourceLineStride lines or more, or a malformed
/// define is an Error naming file and line. Includes are found by a line scan, not a full
/// preprocessor: an #include inside `#if 0` is still read.
Result<PreprocessedShader> preprocessShader(const ShaderFile& root,
                                            std::span<const ShaderDefine> defines,
                                            const ShaderLoader& loader);

}  // namespace terrain::runtime
