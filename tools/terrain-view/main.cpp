// terrain-view: flies through a pyramid in a window (GLFW, OpenGL 4.5) with the runtime's
// streaming, LOD quadtree and tessellated draw — the same frame as terrain-render — under a
// Dear ImGui overlay of live telemetry and controls. docs/viewer.md is its manual.
#include "CommandLine.h"
#include "FrameSizeFlags.h"
#include "KeyBindings.h"
#include "LodFlags.h"
#include "NumberChecks.h"
#include "Viewer.h"
#include "ViewerOptions.h"
#include "terrain/runtime/LodMethod.h"

#include <fmt/core.h>
#include <CLI/CLI.hpp>

#include <string>

namespace {

std::string keyList() {
    std::string text = "\nKeys (also in the overlay's \"Keys\" section):\n";
    for (const auto& control : terrain::view::heldControls()) {
        text += fmt::format("  {:<22} {}\n", control.keys, control.description);
    }
    for (const auto& binding : terrain::view::keyBindings()) {
        text += fmt::format("  {:<22} {}\n", binding.keys, binding.description);
    }
    return text;
}

}  // namespace

int main(int argc, char** argv) {
    using terrain::view::ViewerOptions;
    CLI::App app{
        "Fly through a pyramid (terrain-build's output) in a window: mouse-look and WASD flight, "
        "orbit, jump to coordinates, a live telemetry overlay, camera paths, screenshots and "
        "telemetry logs. Needs a display with OpenGL 4.5 (run it under `xvfb-run -a` without "
        "one). Manual: docs/viewer.md."};
    app.footer(keyList());
    ViewerOptions o;
    app.add_option("pyramid", o.pyramid, "Pyramid folder (terrain-build's output)")->required();
    app.add_option("--path", o.pathFile,
                   "Play this camera path (docs/camera-path.md) from the start; Space pauses");
    app.add_option("--record", o.recordFile,
                   "Record the flight as a camera path from the start, saved at exit or when R "
                   "stops it");
    app.add_option("--screenshot", o.screenshotFile,
                   "Write a PNG of the window (overlay included) at exit");
    app.add_option(
        "--telemetry", o.telemetryFile,
        "Log the per-frame telemetry CSV (docs/telemetry.md) from the start; T stops it");
    app.add_option("--frames", o.frames, "Exit after this many frames");
    app.add_option("--exit-after", o.exitAfterS, "Exit after this many seconds")
        ->check(terrain::tools::nonNegativeNumber());
    app.add_option("--fps", o.fixedFps,
                   "Advance flight time by 1/FPS per frame instead of by the clock (reproducible "
                   "playback, recordings and screenshots)")
        ->check(CLI::Range(0.01, 1e4));
    app.add_flag("--settle", o.settle,
                 "Wait for streaming before each frame (the settled view, e.g. for screenshots)");
    terrain::tools::addFrameSizeFlags(app, o.widthPx, o.heightPx, "Window", 64);
    app.add_flag(
        "--no-vsync", [&o](std::int64_t) { o.vsync = false; },
        "Do not wait for the display's refresh (V toggles)");
    app.add_flag("--no-overlay", o.hideOverlay, "Start with the overlay hidden (F1 toggles)");
    terrain::tools::addErrorPxFlag(app, o.errorPx, " ([ and ] change it)");
    terrain::tools::addMethodFlag(app, o.method,
                                  " (not rtin, lee2011 or ripolles: they stream nothing)");
    terrain::tools::addStreamingBudgetFlags(app, o.budgets);
    app.add_option("--measure-every", o.measureEvery,
                   "Measure triangles and GPU time every N frames (1: every frame; measuring "
                   "waits for the GPU)")
        ->capture_default_str()
        ->check(CLI::Range(1, 100000));
    o.look.addTo(app);
    app.add_flag("--no-fog", o.noFog, "No fog");
    app.add_flag("--orbit", o.orbit, "Start orbiting the point at the centre of the view");
    app.add_option("--goto", o.jumpTo,
                   "Start over world X,Y[,HEIGHT above ground] (a projected pyramid's easting, "
                   "northing; a globe's LATITUDE,LONGITUDE[,ALTITUDE above WGS84])")
        ->delimiter(',')
        ->expected(2, 3);
    app.add_flag("--json", o.json, "Print a JSON summary on stdout at exit");
    if (const auto status = terrain::tools::parseCommandLine(app, argc, argv)) return *status;

    // The viewer streams: the in-core methods (the RTIN yardstick and Lee & Shin, which
    // read the finest level once) are for the benchmark and terrain-render.
    auto method = terrain::runtime::parseLodMethod(o.method);
    if (!method || terrain::runtime::lodMethodInfo(method.value()).inCore) {
        fmt::print(stderr, "terrain-view: --method: {}\n",
                   method ? fmt::format("{} streams nothing (it holds the finest level in "
                                        "memory); the viewer flies the streaming methods "
                                        "(terrain-render and terrain-bench draw it)",
                                        o.method)
                          : method.error().message);
        return 1;
    }
    auto viewer = terrain::view::Viewer::create(o);
    if (!viewer) {
        fmt::print(stderr, "terrain-view: {}\n", viewer.error().message);
        return 1;
    }
    return viewer.value()->run();
}
