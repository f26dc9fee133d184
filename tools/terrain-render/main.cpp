// terrain-render (preview): generates the procedural DEM, renders one tessellated,
// hill-shaded view of it headless (EGL) and writes a PNG plus a JSON summary.
// Until the pyramid, streaming and LOD issues land, this is the project's main job.
#include "GlInfoJson.h"
#include "PreviewRenderer.h"

#include "terrain/io/ProceduralTerrain.h"
#include "terrain/io/RgbaImageWriter.h"
#include "terrain/runtime/HeadlessGlContext.h"

#include <fmt/core.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

int fail(const std::string& message) {
    fmt::print(stderr, "terrain-render: {}\n", message);
    return 1;
}

}  // namespace

int main(int argc, char** argv) {
    using namespace terrain;
    CLI::App app{
        "Render a tessellated, hill-shaded view of the built-in procedural terrain headless "
        "(EGL) to a PNG. Preview: fixed distance-based tessellation, one texture; the "
        "pyramid, streaming and error-driven LOD come with later releases."};
    io::ProceduralTerrainParameters terrain;
    tools::PreviewView view;
    std::string output = "out/terrain.png";
    bool json = false;
    app.add_option("--size", terrain.widthSamples, "DEM side in samples (k·64 + 1)")
        ->capture_default_str();
    app.add_option("--seed", terrain.seed, "Procedural terrain seed")->capture_default_str();
    app.add_option("--spacing", terrain.sampleSpacingM, "Sample spacing in metres")
        ->capture_default_str();
    app.add_option("--width", view.widthPx, "Image width in pixels")
        ->capture_default_str()
        ->check(CLI::Range(16, 16384));
    app.add_option("--height", view.heightPx, "Image height in pixels")
        ->capture_default_str()
        ->check(CLI::Range(16, 16384));
    app.add_option("--pixels-per-segment", view.pixelsPerSegment,
                   "Target projected length of a triangle edge, pixels")
        ->capture_default_str()
        ->check(CLI::Range(0.5, 256.0));
    app.add_option("-o,--output", output, "PNG to write")->capture_default_str();
    app.add_flag("--json", json, "Print a JSON summary on stdout");
    CLI11_PARSE(app, argc, argv);
    terrain.heightSamples = terrain.widthSamples;

    const auto start = Clock::now();
    auto context = runtime::HeadlessGlContext::create();
    if (!context) return fail(context.error().message);
    const runtime::GlInfo& gl = context.value()->info();
    if (terrain.widthSamples > gl.maxTextureSize)
        return fail(
            fmt::format("--size {} exceeds this GL's largest texture ({}); the preview "
                        "draws the DEM from one texture",
                        terrain.widthSamples, gl.maxTextureSize));

    auto source = io::ProceduralTerrain::create(terrain);
    if (!source) return fail(source.error().message);
    const auto side = terrain.widthSamples;
    std::vector<float> heights(static_cast<std::size_t>(side) * side);
    const auto generateStart = Clock::now();
    source.value().fillWindow(0, 0, side, side, heights,
                              std::max(1u, std::thread::hardware_concurrency()));
    const double generateSeconds = secondsSince(generateStart);

    auto renderer = tools::PreviewRenderer::create(heights, static_cast<int>(side),
                                                   terrain.sampleSpacingM, view);
    if (!renderer) return fail(renderer.error().message);
    const auto renderStart = Clock::now();
    const tools::PreviewFrame frame = renderer.value().render();
    const double renderSeconds = secondsSince(renderStart);

    const auto glErrors = context.value()->debugLog().errorCount();
    if (glErrors > 0) return fail(fmt::format("{} OpenGL error(s) while rendering", glErrors));

    std::error_code ec;
    const std::filesystem::path outputPath(output);
    if (outputPath.has_parent_path())
        std::filesystem::create_directories(outputPath.parent_path(), ec);
    if (auto written = io::writeRgba8Png(outputPath, view.widthPx, view.heightPx, frame.rgba);
        !written)
        return fail(written.error().message);

    if (json) {
        const nlohmann::json summary{
            {"tool", "terrain-render"},
            {"mode", "preview: one texture, distance-based power-of-two tessellation factors"},
            {"output", output},
            {"terrain",
             {{"source", "procedural"},
              {"seed", terrain.seed},
              {"sizeSamples", side},
              {"sampleSpacingM", terrain.sampleSpacingM}}},
            {"image", {{"widthPx", view.widthPx}, {"heightPx", view.heightPx}}},
            {"patches", frame.patches},
            {"trianglesGenerated", frame.trianglesGenerated},
            {"drawCalls", 1},
            {"gpuTimeMs", frame.gpuMs},
            {"gpuTimeNote", gl.renderer.find("llvmpipe") != std::string::npos
                                ? "llvmpipe rasterises on the CPU after the query ends: "
                                  "gpuTimeMs is not a frame time there; see renderSeconds"
                                : "GL_TIME_ELAPSED of the draw"},
            {"generateSeconds", generateSeconds},
            {"renderSeconds", renderSeconds},  // draw + wait + read back
            {"totalSeconds", secondsSince(start)},
            {"gl", tools::glInfoJson(gl)},
        };
        std::puts(summary.dump(2).c_str());
    } else {
        fmt::print(stderr,
                   "terrain-render: wrote {} ({}x{}, {} triangles, {} patches, {:.1f} ms draw)\n",
                   output, view.widthPx, view.heightPx, frame.trianglesGenerated, frame.patches,
                   frame.gpuMs);
    }
    return 0;
}
