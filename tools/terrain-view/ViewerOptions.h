// ViewerOptions: terrain-view's command line (main.cpp parses it; docs/viewer.md lists it).
#pragma once

#include "DrawStyleFlags.h"
#include "StreamingBudgetFlags.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace terrain::view {

struct ViewerOptions {
    std::string pyramid;
    std::string pathFile;        ///< play this camera path from the start
    std::string recordFile;      ///< record a camera path from the start, saved at exit / R
    std::string screenshotFile;  ///< written at exit
    std::string telemetryFile;   ///< telemetry CSV from the start
    std::uint64_t frames = 0;    ///< exit after this many frames (0: run until closed)
    double exitAfterS = 0.0;     ///< exit after this many seconds (0: run until closed)
    double fixedFps = 0.0;       ///< > 0: time advances 1 / fixedFps per frame (deterministic)
    bool settle = false;         ///< wait for streaming before each frame
    int widthPx = 1280;
    int heightPx = 800;
    bool vsync = true;
    bool hideOverlay = false;
    double errorPx = 2.0;
    /// A streaming LOD method (LodMethod.h): every method but the RTIN.
    std::string method = "yusov2011";
    tools::StreamingBudgets budgets{
        .cpuCacheMiB = 256.0, .gpuLayers = 1024, .uploadMiBPerFrame = 16.0};
    int measureEvery = 30;  ///< measure triangles and GPU time every this many frames
    tools::DrawStyleFlags look;
    bool noFog = false;
    bool orbit = false;          ///< start orbiting the view's centre
    std::vector<double> jumpTo;  ///< X Y [height above ground]: start there
    bool json = false;
};

}  // namespace terrain::view
