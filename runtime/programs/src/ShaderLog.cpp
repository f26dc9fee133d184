// Driver log formats -> "<file>:<line>: message". Driver quirks of log formats live here:
// - Mesa (22.3): errors found after parsing (undeclared names, type errors) carry source
//   string 0 whatever #line said, because its parser's default location rule resets the
//   source; only the line survives. Hence the file is decoded from the line number
//   (kSourceLineStride) and the reported source-string number is ignored.
#include "terrain/runtime/ShaderLog.h"

#include "terrain/runtime/ShaderPreprocessor.h"

#include <cctype>
#include <optional>

namespace terrain::runtime {
namespace {

/// Reads an unsigned decimal number at the front of `text` and removes it.
std::optional<unsigned long> takeNumber(std::string_view& text) {
    std::size_t digits = 0;
    unsigned long value = 0;
    while (digits < text.size() && std::isdigit(static_cast<unsigned char>(text[digits])) != 0 &&
           digits < 9) {
        value = value * 10 + static_cast<unsigned long>(text[digits] - '0');
        ++digits;
    }
    if (digits == 0) {
        return std::nullopt;
    }
    text.remove_prefix(digits);
    return value;
}

bool takePrefix(std::string_view& text, std::string_view prefix) {
    if (!text.starts_with(prefix)) {
        return false;
    }
    text.remove_prefix(prefix.size());
    return true;
}

struct Location {
    unsigned long source = 0;
    unsigned long line = 0;
    std::optional<unsigned long> column;
    std::string severity;  ///< set when the format puts it before the location
    std::string_view message;
};

/// Mesa: "S:L(C): message".
std::optional<Location> parseMesa(std::string_view text) {
    Location location;
    auto source = takeNumber(text);
    if (!source || !takePrefix(text, ":")) {
        return std::nullopt;
    }
    auto line = takeNumber(text);
    if (!line || !takePrefix(text, "(")) {
        return std::nullopt;
    }
    auto column = takeNumber(text);
    if (!column || !takePrefix(text, "): ")) {
        return std::nullopt;
    }
    location.source = *source;
    location.line = *line;
    location.column = column;
    location.message = text;
    return location;
}

/// NVIDIA: "S(L) : message".
std::optional<Location> parseNvidia(std::string_view text) {
    Location location;
    auto source = takeNumber(text);
    if (!source || !takePrefix(text, "(")) {
        return std::nullopt;
    }
    auto line = takeNumber(text);
    if (!line || !takePrefix(text, ")")) {
        return std::nullopt;
    }
    if (!takePrefix(text, " : ") && !takePrefix(text, ": ")) {
        return std::nullopt;
    }
    location.source = *source;
    location.line = *line;
    location.message = text;
    return location;
}

/// AMD and Intel on Windows: "ERROR: S:L: message" / "WARNING: S:L: message".
std::optional<Location> parseSeverityFirst(std::string_view text) {
    Location location;
    if (takePrefix(text, "ERROR: ")) {
        location.severity = "error";
    } else if (takePrefix(text, "WARNING: ")) {
        location.severity = "warning";
    } else {
        return std::nullopt;
    }
    auto source = takeNumber(text);
    if (!source || !takePrefix(text, ":")) {
        return std::nullopt;
    }
    auto line = takeNumber(text);
    if (!line || !takePrefix(text, ": ")) {
        return std::nullopt;
    }
    location.source = *source;
    location.line = *line;
    location.message = text;
    return location;
}

std::string translateLine(std::string_view line, std::span<const std::string> sourceNames) {
    std::optional<Location> location = parseMesa(line);
    if (!location) {
        location = parseNvidia(line);
    }
    if (!location) {
        location = parseSeverityFirst(line);
    }
    if (!location) {
        return std::string(line);
    }
    const unsigned long file = location->line / kSourceLineStride;
    const unsigned long fileLine = location->line % kSourceLineStride;
    std::string text =
        file < sourceNames.size() ? sourceNames[file] : "<source " + std::to_string(file) + ">";
    text += ':' + std::to_string(fileLine);
    if (location->column) {
        text += ':' + std::to_string(*location->column);
    }
    text += ": ";
    if (!location->severity.empty()) {
        text += location->severity + ": ";
    }
    text += location->message;
    return text;
}

}  // namespace

std::string translateShaderLog(std::string_view log, std::span<const std::string> sourceNames) {
    std::string result;
    while (!log.empty()) {
        const std::size_t end = log.find('\n');
        std::string_view line = log.substr(0, end);
        log.remove_prefix(end == std::string_view::npos ? log.size() : end + 1);
        if (!line.empty() && line.back() == '\r') {
            line.remove_suffix(1);
        }
        if (line.empty() || line == std::string_view("\0", 1)) {
            continue;
        }
        if (!result.empty()) {
            result += '\n';
        }
        result += translateLine(line, sourceNames);
    }
    return result;
}

}  // namespace terrain::runtime
