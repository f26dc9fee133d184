// StreamingBudgetFlags: --cpu-cache-mib, --gpu-layers, --upload-mib-per-frame,
// --upload-ms-per-frame, --imagery-gpu-mib, --imagery-cache-mib, --reader-threads,
// --no-prefetch and --read-ahead-frames, the streaming budgets of every program that flies
// through a pyramid, with one meaning and one range each.
#pragma once

#include "terrain/runtime/LodQuadtree.h"
#include "terrain/runtime/TileStreamer.h"

#include <CLI/CLI.hpp>

#include <cstddef>
#include <string>

namespace terrain::tools {

struct StreamingBudgets {
    double cpuCacheMiB = 256.0;
    int gpuLayers = 1024;
    double uploadMiBPerFrame = 16.0;
    double uploadMsPerFrame = 0.0;                   ///< 0: no time budget, the byte budget alone
    double imageryGpuMiB = 256.0;                    ///< the imagery texture array, mips included
    double imageryCacheMiB = 128.0;                  ///< the CPU imagery cache
    /// The I/O's threads reading and decoding; 0: io::defaultReaderThreads(the pyramid).
    int readerThreads = 0;
    bool noPrefetch = false;                         ///< read only the tiles the LOD wants now
    /// Along the camera's motion (LodOptions::readAheadFrames); 0, or --no-prefetch: off.
    double readAheadFrames = runtime::LodOptions{}.readAheadFrames;

    static std::size_t bytesOfMiB(double mib) {
        return static_cast<std::size_t>(mib * 1024.0 * 1024.0);
    }
    /// The budgets as the streamer's options (of its I/O options, the reader threads only).
    /// Imagery uploads get a budget of their own of the same size as the heights'.
    void applyTo(runtime::TileStreamerOptions& options) const {
        options.cpuCacheBytes = bytesOfMiB(cpuCacheMiB);
        options.gpuLayers = gpuLayers;
        options.uploadBytesPerFrame = bytesOfMiB(uploadMiBPerFrame);
        options.uploadMsPerFrame = uploadMsPerFrame;
        options.imagery.gpuBytes = bytesOfMiB(imageryGpuMiB);
        options.imagery.cpuCacheBytes = bytesOfMiB(imageryCacheMiB);
        options.imagery.uploadBytesPerFrame = bytesOfMiB(uploadMiBPerFrame);
        options.io.readerThreads = readerThreads;
        options.prefetch = !noPrefetch;
    }
    /// The reading ahead the LOD asks for (what it asks, the streamer reads: see above).
    void applyTo(runtime::LodOptions& lod) const {
        lod.readAheadFrames = noPrefetch ? 0.0 : readAheadFrames;
    }
};

/// Adds the nine flags, bound to `budgets`, whose values are the defaults shown; `scope`
/// ends each description (" per threshold", say). A CPU cache too small for one tile is
/// refused when the pyramid is opened (TileStreamer::open), which knows the tile size; so
/// are imagery budgets below one imagery tile, when the pyramid has imagery.
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
    app.add_option("--upload-ms-per-frame", budgets.uploadMsPerFrame,
                   "GPU upload time budget per frame of the heights, ms (0: none; at least one "
                   "tile a frame)" +
                       scope)
        ->capture_default_str()
        ->check(CLI::Range(0.0, 1000.0));
    app.add_option(
           "--imagery-gpu-mib", budgets.imageryGpuMiB,
           "GPU imagery texture array budget, MiB (mips included; a tile is 0.33 MiB)" + scope)
        ->capture_default_str()
        ->check(CLI::Range(0.0, 1024.0 * 1024.0));
    app.add_option("--imagery-cache-mib", budgets.imageryCacheMiB,
                   "CPU imagery tile cache budget, MiB (a tile is 0.25 MiB)" + scope)
        ->capture_default_str()
        ->check(CLI::Range(0.0, 1024.0 * 1024.0));
    app.add_option("--reader-threads", budgets.readerThreads,
                   "I/O threads reading and decoding tiles (default 0: min(hardware threads, 4); a "
                   "pyramid at a URL at least as many as TERRAIN_HTTP_MAX_PER_HOST, 6)" +
                       scope)
        ->capture_default_str()
        ->check(CLI::Range(0, 64));
    app.add_flag("--no-prefetch", budgets.noPrefetch,
                 "Read only the tiles the LOD wants now, none of those it expects to want "
                 "(refining then takes a frame a level)" +
                     scope);
    app.add_option("--read-ahead-frames", budgets.readAheadFrames,
                   "Read ahead the children of drawn patches the camera, at its present "
                   "velocity, will want split within this many frames (0: off)" +
                       scope)
        ->capture_default_str()
        ->check(CLI::Range(0.0, 600.0));
}

}  // namespace terrain::tools
