// StreamingBudgetFlags: --cpu-cache-mib, --gpu-layers and --upload-mib-per-frame, the
// streaming budgets of every program that flies through a pyramid, with one meaning and
// one range each.
#pragma once

#include "terrain/runtime/TileStreamer.h"

#include <CLI/CLI.hpp>

#include <cstddef>
#include <string>

namespace terrain::tools {

struct StreamingBudgets {
    double cpuCacheMiB = 256.0;
    int gpuLayers = 1024;
    double uploadMiBPerFrame = 16.0;

    static std::size_t bytesOfMiB(double mib) {
        return static_cast<std::size_t>(mib * 1024.0 * 1024.0);
    }
    /// The budgets as the streamer's options (its I/O options untouched).
    void applyTo(runtime::TileStreamerOptions& options) const {
        options.cpuCacheBytes = bytesOfMiB(cpuCacheMiB);
        options.gpuLayers = gpuLayers;
        options.uploadBytesPerFrame = bytesOfMiB(uploadMiBPerFrame);
    }
};

/// Adds the three flags, bound to `budgets`, whose values are the defaults shown; `scope`
/// ends each description (" per threshold", say). A CPU cache too small for one tile is
/// refused when the pyramid is opened (TileStreamer::open), which knows the tile size.
inline void addStreamingBudgetFlags(CLI::App& app, StreamingBudgets& budgets,
                                    const std::string& scope = "") {
    app.add_option("--cpu-cache-mib", budgets.cpuCacheMiB, "CPU tile cache budget, MiB" + scope)
        ->capture_default_str()
        ->check(CLI::Range(0.0, 1024.0 * 1024.0));
    app.add_option("--gpu-layers", budgets.gpuLayers,
                   "GPU tile pool layers (tiles resident on the GPU)" + scope)
        ->capture_default_str()
        ->check(CLI::Range(1, 1 << 16));
    app.add_option("--upload-mib-per-frame", budgets.uploadMiBPerFrame,
                   "GPU upload budget per frame, MiB (at least one tile a frame)" + scope)
        ->capture_default_str()
        ->check(CLI::Range(0.0, 4096.0));
}

}  // namespace terrain::tools
