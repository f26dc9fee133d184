// LodFlags: --error-px, --max-sample-px and --method, the LOD's thresholds and method, declared
// once for every
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

/// Adds --max-sample-px (LodOptions::maxSamplePx: the most pixels a drawn patch's sample may
/// span, 0 for the geometric bound alone), bound to `maxSamplePx`.
inline CLI::Option* addMaxSamplePxFlag(CLI::App& app, double& maxSamplePx) {
    return app
        .add_option("--max-sample-px", maxSamplePx,
                    "yusov2011: split a patch whose samples span more pixels than this, so the "
                    "shading is as fine as the pixel whichever level draws it (0: the "
                    "geometric bound alone)")
        ->capture_default_str()
        ->check(CLI::Range(0.0, 1e4));
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
