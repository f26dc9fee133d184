// ShaderLog: rewrites a driver's compile log so each message starts "<file>:<line>:",
// decoding the line numbers of the #line directives the preprocessor wrote.
#pragma once

#include <span>
#include <string>
#include <string_view>

namespace terrain::runtime {

/// Rewrites every log line in a known driver format; other lines pass through unchanged.
///   Mesa:         "0:12(5): error: ..."      -> "<file>:12:5: error: ..."
///   NVIDIA:       "0(12) : error C0000: ..." -> "<file>:12: error C0000: ..."
///   AMD / Intel:  "ERROR: 0:12: ..."         -> "<file>:12: error: ..."
/// A reported line L is line L % kSourceLineStride of file sourceNames[L / kSourceLineStride]
/// (see ShaderPreprocessor.h); a file number past the list is written "<source n>".
std::string translateShaderLog(std::string_view log, std::span<const std::string> sourceNames);

}  // namespace terrain::runtime
