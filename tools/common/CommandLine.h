// parseCommandLine: every program's command line parsed one way. A bad option or value is
// bad input like any other, exit status 1 (CLI11_PARSE returned CLI11's own codes, 104 to
// 114, which no script or page of ours knows); --help and --version still exit 0.
#pragma once

#include <CLI/CLI.hpp>

#include <optional>

namespace terrain::tools {

/// Parses the command line into `app`'s options. nullopt: the program goes on; else the
/// status it exits with, CLI11's message (or help) printed: 0 after --help or --version,
/// 1 after a bad option or value.
inline std::optional<int> parseCommandLine(CLI::App& app, int argc, const char* const* argv) {
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& error) {
        return app.exit(error) == 0 ? 0 : 1;
    }
    return std::nullopt;
}

}  // namespace terrain::tools
