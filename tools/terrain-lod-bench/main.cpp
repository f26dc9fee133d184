// terrain-lod-bench: CPU time of the coarse LOD per frame on a smooth flight: the
// frame-coherent LodQuadtree against selecting from the root every frame (selectPatches),
// on the same frames with the same resident tiles. Each frame first lets streaming catch
// up (so both see a settled view, and the figure is the LOD's, not the disk's), then times
// one update of each. Prints medians, p95 and the speed-up; --json for scripts.
#include "CommandLine.h"
#include "FrameSizeFlags.h"
#include "GlInfoJson.h"
#include "LodFlags.h"
#include "StreamingBudgetFlags.h"

#include "terrain/gl/HeadlessGlContext.h"
#include "terrain/runtime/LatencyHistogram.h"
#include "terrain/runtime/LodQuadtree.h"
#include "terrain/runtime/PatchSelection.h"
#include "terrain/runtime/PlaneSurface.h"
#include "terrain/runtime/TerrainGeometry.h"
#include "terrain/runtime/TileStreamer.h"

#include <fmt/core.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;
using namespace terrain;

int fail(const std::string& message) {
    fmt::print(stderr, "terrain-lod-bench: {}\n", message);
    return 1;
}

double microsecondsSince(Clock::time_point start) {
    return std::chrono::duration<double, std::micro>(Clock::now() - start).count();
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{
        "LOD update CPU time per frame on a smooth flight: the frame-coherent quadtree "
        "against re-selecting from the root every frame."};
    std::string pyramid;
    int width = 1920, height = 1080, frames = 600;
    // Budgets large enough that streaming never limits the LOD being timed.
    tools::StreamingBudgets budgets{
        .cpuCacheMiB = 1024.0, .gpuLayers = 4096, .uploadMiBPerFrame = 256.0};
    double errorPx = 2.0, speedMps = 150.0, altitudeM = 200.0, fovDegrees = 60.0;
    bool json = false;
    app.add_option("pyramid", pyramid, "Pyramid folder")->required();
    tools::addFrameSizeFlags(app, width, height, "Viewport");
    tools::addErrorPxFlag(app, errorPx);
    app.add_option("--frames", frames, "Frames of the flight (60 per second of flight)")
        ->capture_default_str();
    app.add_option("--speed-mps", speedMps, "Flight speed")->capture_default_str();
    app.add_option("--altitude-m", altitudeM, "Height above the DEM's highest point")
        ->capture_default_str();
    tools::addStreamingBudgetFlags(app, budgets);
    app.add_flag("--json", json, "Print a JSON summary on stdout");
    if (const auto status = terrain::tools::parseCommandLine(app, argc, argv)) return *status;

    auto context = gl::HeadlessGlContext::create();
    if (!context) return fail(context.error().message);
    runtime::TileStreamerOptions options;
    budgets.applyTo(options);
    auto opened = runtime::TileStreamer::open(pyramid, options);
    if (!opened) return fail(opened.error().message);
    runtime::TileStreamer& streamer = *opened.value();
    if (streamer.manifest().globe)
        return fail(pyramid + ": a globe pyramid; the flight along the DEM's diagonal is planar");
    const runtime::PlaneSurface surface(streamer.manifest());
    const runtime::TerrainGeometry& geometry = surface.geometry();
    runtime::LodOptions lodOptions{.errorPx = errorPx};
    budgets.applyTo(lodOptions);
    runtime::LodQuadtree tree(streamer, surface, lodOptions);

    // A straight, level flight along the DEM's diagonal, looking ahead and 15° down.
    const glm::dvec2 size = geometry.demSize();
    runtime::Camera camera;
    camera.viewportWidth = width;
    camera.viewportHeight = height;
    camera.fovY = fovDegrees * std::numbers::pi / 180.0;
    camera.pitch = -15.0 * std::numbers::pi / 180.0;
    const glm::dvec2 from = geometry.worldAtFraction(0.2, 0.2);
    const glm::dvec2 direction = glm::normalize(glm::dvec2(size.x, -size.y));
    camera.yaw = std::atan2(direction.x, direction.y);

    std::vector<runtime::PatchDraw> treeDraws, rootDraws;
    runtime::LatencyHistogram treeUs, rootUs;
    double treeSum = 0.0, rootSum = 0.0;
    std::uint64_t drawnSum = 0, evaluationsSum = 0, mismatchedFrames = 0;
    const auto runFrame = [&](auto&& body) {
        streamer.beginFrame();
        body();
        runtime::FrameTelemetry t;
        streamer.endFrame(t);
    };
    for (int frame = 0; frame < frames; ++frame) {
        const double distance = speedMps * frame / 60.0;
        camera.position = {from.x + direction.x * distance, from.y + direction.y * distance,
                           geometry.maxHeight() + altitudeM};
        // The tree's update is timed first at each new position, one frame's travel from
        // the last: the steady-state cost of a frame of smooth flight (due decisions, new
        // requests, culling, the draw list).
        runtime::LodUpdateStats stats;
        runFrame([&] {
            const auto start = Clock::now();
            stats = tree.update(camera, treeDraws);
            const double us = microsecondsSince(start);
            treeUs.add(us / 1000.0);  // LatencyHistogram counts milliseconds
            treeSum += us;
        });
        // Streaming catches up, untimed, so both see the same settled residency.
        for (int settle = 0; settle < 10000; ++settle) {
            runtime::LodUpdateStats s;
            runFrame([&] { s = tree.update(camera, treeDraws); });
            if (s.waitingSplits == 0 && streamer.loadsOutstanding() == 0) break;
            streamer.waitForReads(std::chrono::milliseconds(100));
        }
        // Selecting from the root, on the settled view at the same position.
        runFrame([&] {
            const auto start = Clock::now();
            runtime::selectPatches(camera, geometry,
                                   lodOptions.coarseErrorPx(runtime::SurfaceKind::Plane), streamer,
                                   rootDraws);
            const double us = microsecondsSince(start);
            rootUs.add(us / 1000.0);
            rootSum += us;
        });
        drawnSum += treeDraws.size();
        evaluationsSum += stats.evaluations;
        if (treeDraws.size() != rootDraws.size()) ++mismatchedFrames;
    }
    const double treeMedianUs = treeUs.percentile(50.0) * 1000.0;
    const double rootMedianUs = rootUs.percentile(50.0) * 1000.0;
    if (json) {
        const nlohmann::json out{
            {"tool", "terrain-lod-bench"},
            {"pyramid", pyramid},
            {"viewport", {width, height}},
            {"error_px", errorPx},
            {"frames", frames},
            {"speed_mps", speedMps},
            {"mean_patches_drawn", static_cast<double>(drawnSum) / frames},
            {"mean_evaluations_per_frame", static_cast<double>(evaluationsSum) / frames},
            {"frames_with_different_cuts", mismatchedFrames},
            {"tree_update_us",
             {{"p50", treeMedianUs},
              {"p95", treeUs.percentile(95.0) * 1000.0},
              {"max", treeUs.max() * 1000.0},
              {"mean", treeSum / frames}}},
            {"from_root_us",
             {{"p50", rootMedianUs},
              {"p95", rootUs.percentile(95.0) * 1000.0},
              {"max", rootUs.max() * 1000.0},
              {"mean", rootSum / frames}}},
            {"speedup_median", rootMedianUs / treeMedianUs},
            {"gl", tools::glInfoJson(*context.value())},
        };
        std::puts(out.dump(2).c_str());
    }
    fmt::print(
        stderr,
        "terrain-lod-bench: {} frames at {}x{}, ε = {} px, {:.0f} patches drawn on average: "
        "quadtree update median {:.1f} µs (p95 {:.1f}), from the root {:.1f} µs (p95 {:.1f}): "
        "{:.1f}x; {} frames with different cuts (hysteresis)\n",
        frames, width, height, errorPx, static_cast<double>(drawnSum) / frames, treeMedianUs,
        treeUs.percentile(95.0) * 1000.0, rootMedianUs, rootUs.percentile(95.0) * 1000.0,
        rootMedianUs / treeMedianUs, mismatchedFrames);
    return 0;
}
