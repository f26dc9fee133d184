// FrameSizeFlags: --width and --height of the frames (or window) a program renders, with
// one range for every program.
#pragma once

#include <CLI/CLI.hpp>

#include <string>

namespace terrain::tools {

/// Adds --width and --height, bound to `widthPx` and `heightPx` (their values are the
/// defaults shown); `what` names the surface ("Frame", "Window", "Viewport").
inline void addFrameSizeFlags(CLI::App& app, int& widthPx, int& heightPx,
                              const std::string& what = "Frame", int minPx = 16) {
    app.add_option("--width", widthPx, what + " width, pixels")
        ->capture_default_str()
        ->check(CLI::Range(minPx, 16384));
    app.add_option("--height", heightPx, what + " height, pixels")
        ->capture_default_str()
        ->check(CLI::Range(minPx, 16384));
}

}  // namespace terrain::tools
