// LodFlags: --error-px and --method, the LOD's threshold and method, declared once for every
// program that flies a LOD (terrain-render, terrain-view, terrain-stress, terrain-lod-bench),
// with one meaning and one range each. terrain-bench sweeps several (--thresholds, --methods).
#pragma once

#include "terrain/runtime/LodMethod.h"

#include <CLI/CLI.hpp>

#include <string>

namespace terrain::tools {

/// Adds --error-px (ε, pixels), bound to `errorPx`, whose value is the default shown; `note`
/// ends the description.
inline CLI::Option* addErrorPxFlag(CLI::App& app, double& errorPx, const std::string& note = "") {
    return app.add_option("--error-px", errorPx, "Screen-space error threshold ε, pixels" + note)
        ->capture_default_str()
        ->check(CLI::Range(0.05, 1e4));
}

/// Adds --method (a name of docs/lod-methods.md), bound to `method`; `note` ends the
/// description (which methods the program refuses, say).
inline CLI::Option* addMethodFlag(CLI::App& app, std::string& method,
                                  const std::string& note = "") {
    return app
        .add_option("--method", method,
                    "LOD method (docs/lod-methods.md): " + runtime::lodMethodNames() + note)
        ->capture_default_str();
}

}  // namespace terrain::tools
