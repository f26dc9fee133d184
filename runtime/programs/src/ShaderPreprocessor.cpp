// #version, #defines, #include inlining and #line bookkeeping for GLSL stage files.
// Core GLSL has no #include (GL_ARB_shading_language_include is not universal), so the
// program builder resolves it; `#line <n * kSourceLineStride + line> <n>` keeps messages
// pointing at the original files: n = 0 is the stage file, 1.. the included files.
#include "terrain/runtime/ShaderPreprocessor.h"

#include <algorithm>
#include <cctype>
#include <optional>

namespace terrain::runtime {
namespace {

/// Nested includes deeper than this are a mistake (and would blow the stack on a cycle
/// that slipped past the check).
constexpr int kMaxIncludeDepth = 32;

bool isIdentifier(std::string_view text) {
    if (text.empty() || std::isdigit(static_cast<unsigned char>(text.front())) != 0) {
        return false;
    }
    return std::all_of(text.begin(), text.end(), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_';
    });
}

std::string_view trimLeft(std::string_view text) {
    while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) {
        text.remove_prefix(1);
    }
    return text;
}

/// If `line` is a preprocessor directive named `directive`, the text after it.
std::optional<std::string_view> directiveArgument(std::string_view line,
                                                  std::string_view directive) {
    line = trimLeft(line);
    if (line.empty() || line.front() != '#') {
        return std::nullopt;
    }
    line = trimLeft(line.substr(1));
    if (!line.starts_with(directive)) {
        return std::nullopt;
    }
    line.remove_prefix(directive.size());
    if (!line.empty() && line.front() != ' ' && line.front() != '\t' && line.front() != '"' &&
        line.front() != '<') {
        return std::nullopt;  // e.g. "#includes" or "#versionX"
    }
    return trimLeft(line);
}

class Preprocessor {
public:
    explicit Preprocessor(const ShaderLoader& loader) : m_loader(loader) {}

    Status run(const ShaderFile& root, std::span<const ShaderDefine> defines) {
        m_output += kGlslVersionLine;
        m_output += '\n';
        for (const ShaderDefine& define : defines) {
            if (!isIdentifier(define.name)) {
                return Error{root.displayName + ": define '" + define.name +
                             "' is not an identifier"};
            }
            if (define.value.find_first_of("\r\n") != std::string::npos) {
                return Error{root.displayName + ": define '" + define.name +
                             "' has a line break in its value"};
            }
            m_output += "#define " + define.name;
            if (!define.value.empty()) {
                m_output += ' ' + define.value;
            }
            m_output += '\n';
        }
        return emitFile(root, 0);
    }

    PreprocessedShader result() && {
        return PreprocessedShader{std::move(m_output), std::move(m_sourceNames)};
    }

private:
    int sourceNumberOf(const std::string& displayName) {
        const auto found = std::find(m_sourceNames.begin(), m_sourceNames.end(), displayName);
        if (found != m_sourceNames.end()) {
            return static_cast<int>(found - m_sourceNames.begin());
        }
        m_sourceNames.push_back(displayName);
        return static_cast<int>(m_sourceNames.size()) - 1;
    }

    Status emitFile(const ShaderFile& file, int depth) {
        const int source = sourceNumberOf(file.displayName);
        m_includeStack.push_back(file.displayName);
        // "#line L N": the next line is line L of source string N (GLSL 4.50 §3.4; before
        // GLSL 3.30 it was the line after, one reason the version is fixed).
        const auto lineDirective = [source](unsigned long line) {
            return "#line " +
                   std::to_string(static_cast<unsigned long>(source) * kSourceLineStride + line) +
                   ' ' + std::to_string(source) + '\n';
        };
        m_output += lineDirective(1);

        std::string_view text = file.text;
        int lineNumber = 0;
        while (!text.empty()) {
            const std::size_t end = text.find('\n');
            std::string_view line = text.substr(0, end);
            text.remove_prefix(end == std::string_view::npos ? text.size() : end + 1);
            ++lineNumber;
            const std::string location = file.displayName + ":" + std::to_string(lineNumber);
            if (static_cast<unsigned long>(lineNumber) >= kSourceLineStride) {
                return Error{location + ": shader files are limited to " +
                             std::to_string(kSourceLineStride - 1) + " lines"};
            }

            if (directiveArgument(line, "version")) {
                return Error{location +
                             ": remove the #version line; the program builder "
                             "adds '" +
                             std::string(kGlslVersionLine) + "'"};
            }
            const auto include = directiveArgument(line, "include");
            if (!include) {
                m_output += line;
                m_output += '\n';
                continue;
            }

            auto name = parseIncludeName(*include);
            if (!name) {
                return Error{location + ": write includes as #include \"Name\""};
            }
            if (depth + 1 >= kMaxIncludeDepth) {
                return Error{location + ": includes nested deeper than " +
                             std::to_string(kMaxIncludeDepth)};
            }
            auto included = m_loader.load(*name);
            if (!included) {
                return Error{location + ": cannot include \"" + *name +
                             "\": " + included.error().message};
            }
            const ShaderFile& child = included.value();
            if (std::find(m_includeStack.begin(), m_includeStack.end(), child.displayName) !=
                m_includeStack.end()) {
                return Error{location + ": include cycle through \"" + *name + "\""};
            }
            if (auto status = emitFile(child, depth + 1); !status) {
                return status;
            }
            // Back in this file: the line after the include.
            m_output += lineDirective(static_cast<unsigned long>(lineNumber) + 1);
        }
        m_includeStack.pop_back();
        return {};
    }

    static std::optional<std::string> parseIncludeName(std::string_view argument) {
        if (argument.size() < 2 || argument.front() != '"') {
            return std::nullopt;
        }
        const std::size_t close = argument.find('"', 1);
        if (close == std::string_view::npos || close == 1) {
            return std::nullopt;
        }
        std::string_view rest = trimLeft(argument.substr(close + 1));
        if (!rest.empty() && rest.back() == '\r') {
            rest.remove_suffix(1);
        }
        if (!rest.empty() && !rest.starts_with("//")) {
            return std::nullopt;
        }
        return std::string(argument.substr(1, close - 1));
    }

    const ShaderLoader& m_loader;
    std::string m_output;
    std::vector<std::string> m_sourceNames;
    std::vector<std::string> m_includeStack;
};

}  // namespace

Result<PreprocessedShader> preprocessShader(const ShaderFile& root,
                                            std::span<const ShaderDefine> defines,
                                            const ShaderLoader& loader) {
    Preprocessor preprocessor(loader);
    if (auto status = preprocessor.run(root, defines); !status) {
        return status.error();
    }
    return std::move(preprocessor).result();
}

}  // namespace terrain::runtime
