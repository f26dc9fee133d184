// terrain-render: flies a camera path through a pyramid headless (EGL) with the runtime's
// streaming, LOD quadtree and tessellated draw, writes PNG frames, the per-frame telemetry
// CSV (streaming and cache columns joined with triangles, patches, draw calls, LOD update
// time and GPU time) and a --json summary. Without --settle it shows what a real-time user
// would see: tiles that have not arrived yet are drawn by their coarser ancestors.
#include "CommandLine.h"
#include "DrawStyleFlags.h"
#include "FaultPrinter.h"
#include "FramePacer.h"
#include "FrameSizeFlags.h"
#include "FullDetailClock.h"
#include "GlImagePng.h"
#include "GlInfoJson.h"
#include "GlobeFlags.h"
#include "LodFlags.h"
#include "NumberChecks.h"
#include "StreamingBudgetFlags.h"
#include "SurfaceKit.h"

#include "terrain/gl/Framebuffer.h"
#include "terrain/gl/HeadlessGlContext.h"
#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/runtime/FlightPath.h"
#include "terrain/runtime/LodStrategyFactory.h"
#include "terrain/runtime/TelemetryCsvWriter.h"
#include "terrain/runtime/TelemetrySummary.h"
#include "terrain/runtime/TerrainSession.h"

#include <epoxy/gl.h>
#include <fmt/core.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;
using namespace terrain;

struct RenderOptions {
    std::string pyramid;
    std::string pathFile;
    std::string savePath;
    std::string outputDir = "out/render";
    int widthPx = 960;
    int heightPx = 540;
    double errorPx = 2.0;
    double maxSamplePx = runtime::TerrainSessionOptions{}.lod.maxSamplePx;
    std::string method = "yusov2011";
    bool ripollesNoCoherence = false;
    double fps = 30.0;
    double durationS = 0.0;  // of the default path; 0: 20 s
    std::uint64_t frames = 0;
    std::uint64_t every = 30;
    std::vector<std::uint64_t> frameList;
    bool settle = false;
    tools::StreamingBudgets budgets{
        .cpuCacheMiB = 256.0, .gpuLayers = 1024, .uploadMiBPerFrame = 16.0};
    tools::DrawStyleFlags look;
    tools::GlobeFlags globe;
    bool json = false;
};

int fail(const std::string& message) {
    fmt::print(stderr, "terrain-render: {}\n", message);
    return 1;
}

nlohmann::json statsJson(const runtime::LatencyHistogram& h, double scale = 1.0) {
    const auto value = [&](double v) {
        return std::isnan(v) ? nlohmann::json() : nlohmann::json(v * scale);
    };
    return {{"p50", value(h.percentile(50.0))},
            {"p95", value(h.percentile(95.0))},
            {"max", value(h.max())},
            {"mean", value(h.mean())}};
}

// One flight on either surface; what differs between the plane and the globe comes from the
// pyramid's SurfaceKit.
int run(const RenderOptions& o) {
    const auto start = Clock::now();
    auto context = gl::HeadlessGlContext::create();
    if (!context) return fail(context.error().message);
    auto manifest = io::readManifest(o.pyramid);
    if (!manifest) return fail(manifest.error().message);
    const std::unique_ptr<tools::SurfaceKit> kit = tools::SurfaceKit::of(manifest.value());

    runtime::TerrainSessionOptions sessionOptions;
    o.budgets.applyTo(sessionOptions.streaming);
    o.budgets.applyTo(sessionOptions.lod);
    sessionOptions.lod.errorPx = o.errorPx;
    sessionOptions.lod.maxSamplePx = o.maxSamplePx;
    sessionOptions.lod.horizonCulling = !o.globe.noHorizonCulling;
    auto method = runtime::parseLodMethod(o.method);
    if (!method) return fail("--method: " + method.error().message);
    if (Status supported = kit->supports(o.pyramid, method.value()); !supported)
        return fail(supported.error().message);
    if (Status own = kit->refuseForeignFlags(o.pyramid, o.globe); !own)
        return fail(own.error().message);
    sessionOptions.method = method.value();
    sessionOptions.ripolles.coherence = !o.ripollesNoCoherence;
    auto opened = runtime::openLodStrategy(o.pyramid, sessionOptions);
    if (!opened) return fail(opened.error().message);
    runtime::LodStrategy& session = *opened.value();
    // The streaming methods' streamer: faults, load latencies (null for the RTIN).
    auto* const streaming = dynamic_cast<runtime::TerrainSession*>(opened.value().get());

    auto flown = kit->flight(o.pyramid, session.surface(), o.pathFile,
                             o.durationS > 0.0 ? o.durationS : 20.0, o.globe);
    if (!flown) return fail(flown.error().message);
    if (!flown.value().said.empty()) fmt::print(stderr, "terrain-render: {}\n", flown.value().said);
    const runtime::FlightPath& path = flown.value().path;
    if (!o.savePath.empty()) {
        if (auto saved = path.save(o.savePath); !saved) return fail(saved.error().message);
    }

    std::error_code ec;
    std::filesystem::create_directories(o.outputDir, ec);
    if (ec) return fail(fmt::format("{}: cannot create the folder: {}", o.outputDir, ec.message()));
    const std::filesystem::path outputDir(o.outputDir);
    auto csv = runtime::TelemetryCsvWriter::create(outputDir / "telemetry.csv");
    if (!csv) return fail(csv.error().message);

    auto framebuffer = gl::Framebuffer::create(o.widthPx, o.heightPx, "terrain-render frame");
    if (!framebuffer) return fail(framebuffer.error().message);

    runtime::TerrainStyle style;
    style.measure = true;
    kit->applyLook(style, o.look, session.surface());
    const std::array<float, 4> sky{style.skyColor[0], style.skyColor[1], style.skyColor[2], 1.0f};

    runtime::Camera camera;
    camera.viewportWidth = o.widthPx;
    camera.viewportHeight = o.heightPx;
    camera.nearPlane = 0.5;  // the plane's; a globe path sets its own (placeOnGlobe)
    const double durationS = path.durationS();
    const std::uint64_t frames =
        o.frames > 0 ? o.frames : static_cast<std::uint64_t>(std::floor(durationS * o.fps)) + 1;
    const std::set<std::uint64_t> chosen(o.frameList.begin(), o.frameList.end());

    runtime::TelemetrySummary summary;
    runtime::LatencyHistogram lodUs, gpuMs, triangles;
    std::uint64_t framesWritten = 0, maxDrawCalls = 0, maxTriangles = 0, maxPatches = 0;
    tools::FlightFacts facts;
    facts.pathFile = o.pathFile;
    facts.fixedPose = o.globe.fixedPose();
    facts.fps = o.fps;
    facts.horizonCulling = !o.globe.noHorizonCulling;
    // Faults on stderr as they happen; a root that cannot be read ends the run (every frame
    // would be empty, or on a globe a cube face would show the bare ellipsoid instead of its
    // data: nothing is left to draw in its place).
    tools::FaultPrinter faults("terrain-render");
    const auto fatal = [&]() -> std::optional<std::string> {
        if (streaming != nullptr) faults.printNew(streaming->streamer());
        if (const runtime::TileFault* fault = session.fatalFault())
            return std::string(kit->rootFaultMessage()) + fault->message;
        return std::nullopt;
    };
    // One frame as a user would see it: the LOD update, the draw into the framebuffer.
    struct DrawnFrame {
        runtime::TerrainDrawStats drawn;
        runtime::LodUpdateStats lod;      ///< as the update left it
        std::uint64_t waitingSplits = 0;  ///< after the frame
    };
    const auto drawFrame = [&](runtime::FrameTelemetry& t) {
        DrawnFrame f;
        const runtime::LodUpdateStats& lod = session.beginFrame(camera);
        f.lod = lod;
        framebuffer.value().clear(sky, 0.0f);  // reversed Z: far is 0
        glBindFramebuffer(GL_FRAMEBUFFER, framebuffer.value().id());
        glViewport(0, 0, o.widthPx, o.heightPx);
        f.drawn = session.draw(camera, style);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        session.endFrame(t);
        f.waitingSplits = lod.waitingSplits;
        return f;
    };
    // Without --settle, frames at most fps a second, as a display shows them (FramePacer.h):
    // where frames are drawn fast the camera moves at the path's own speed, and a cold start
    // does not race through the path before its first tile is in.
    tools::FramePacer pacer(1.0 / o.fps);
    const auto loopStart = Clock::now();
    auto previous = loopStart;
    for (std::uint64_t frame = 0; frame < frames; ++frame) {
        if (!o.settle) pacer.waitForNextFrame();
        path.apply(kit->frameTimeS(path, frame, frames, o.fps), camera);
        if (o.settle && !session.settle(camera, std::chrono::seconds(60))) {
            if (auto broken = fatal()) return fail(*broken);
            return fail(fmt::format("frame {}: streaming did not settle within 60 s", frame));
        }
        runtime::FrameTelemetry t;
        const DrawnFrame drawnFrame = drawFrame(t);
        const runtime::TerrainDrawStats& drawn = drawnFrame.drawn;
        facts.horizonCulled += drawnFrame.lod.horizonCulled;
        facts.visited += drawnFrame.lod.visited;
        if (auto broken = fatal()) return fail(*broken);
        if ((o.every > 0 && frame % o.every == 0) || chosen.contains(frame) ||
            frame + 1 == frames) {
            const auto file = outputDir / fmt::format("frame-{:05}.png", frame);
            if (auto written = tools::writeFramebufferPng(framebuffer.value(), file); !written)
                return fail(written.error().message);
            ++framesWritten;
        }
        const auto now = Clock::now();
        t.frame = frame;
        t.timeS = std::chrono::duration<double>(now - loopStart).count();
        t.frameMs = std::chrono::duration<double, std::milli>(now - previous).count();
        previous = now;
        csv.value().write(t);
        summary.add(t);
        lodUs.add(t.lodUpdateUs / 1000.0);  // LatencyHistogram counts milliseconds
        if (!std::isnan(t.gpuMs)) gpuMs.add(t.gpuMs);
        triangles.add(static_cast<double>(drawn.triangles) / 1000.0);
        maxDrawCalls = std::max<std::uint64_t>(maxDrawCalls, t.drawCalls);
        maxTriangles = std::max<std::uint64_t>(maxTriangles, drawn.triangles);
        maxPatches = std::max<std::uint64_t>(maxPatches, t.patchesDrawn);
        if (context.value()->debugLog().errorCount() > 0)
            return fail("OpenGL reported an error:\n" + context.value()->debugLog().formatErrors());
    }
    if (auto closed = csv.value().close(); !closed) return fail(closed.error().message);
    facts.lastCamera = camera;
    // Time to full detail after arriving at the path's end: the last pose held, frames drawn as a
    // user would see them, until no split waits for a tile, no imagery tile the view wants is
    // missing, and nothing is loading (not with --settle, whose frames are all settled). The
    // heights and the imagery are also timed apart.
    if (!o.settle && streaming != nullptr) {
        tools::FullDetailClock clock;
        while (!clock.reached() && clock.seconds() < 60.0) {
            clock.waitForNextFrame();
            runtime::FrameTelemetry t;
            const std::uint64_t waitingSplits = drawFrame(t).waitingSplits;
            if (auto broken = fatal()) return fail(*broken);
            clock.frameEnded(session, waitingSplits);
        }
        facts.arrival = clock.result();
    }
    // A last frame with nothing drawn: wait for what streaming still owes it, so a root that
    // cannot be read is this error rather than an empty picture and exit status 0.
    if (streaming != nullptr && streaming->draws().empty()) {
        session.settle(camera, std::chrono::seconds(60));
        if (auto broken = fatal()) return fail(*broken);
    }
    nlohmann::json surfaceFields = nlohmann::json::object();
    if (streaming != nullptr) facts.lastDraws = streaming->draws();
    kit->addJsonFields(surfaceFields, facts);
    if (streaming != nullptr) {
        summary.mergeLoadLatencies(streaming->streamer().loadLatencies());
        streaming->streamer().drain(std::chrono::seconds(10));
        faults.printRest(streaming->streamer());
    }
    const bool llvmpipe = context.value()->info().renderer.find("llvmpipe") != std::string::npos;

    if (o.json) {
        nlohmann::json out{
            {"tool", "terrain-render"},
            {"pyramid", o.pyramid},
            {"tiling", kit->tiling()},
            {"path_duration_s", durationS},
            {"frames", frames},
            {"frames_written", framesWritten},
            {"output_dir", o.outputDir},
            {"telemetry_csv", (outputDir / "telemetry.csv").string()},
            {"width_px", o.widthPx},
            {"height_px", o.heightPx},
            {"method", o.method},
            {"error_px", o.errorPx},
            {"max_sample_px", o.maxSamplePx},
            {"settle", o.settle},
            {"triangles",
             {{"p50", triangles.percentile(50.0) * 1000.0},
              {"max", maxTriangles},
              {"mean", triangles.mean() * 1000.0}}},
            {"patches_drawn_max", maxPatches},
            {"draw_calls_max", maxDrawCalls},
            {"lod_update_us", statsJson(lodUs, 1000.0)},
            {"gpu_ms", statsJson(gpuMs)},
            {"gpu_ms_note", llvmpipe ? "llvmpipe rasterises on the CPU after the query ends: "
                                       "gpu_ms is not a frame time there"
                                     : "GL_TIME_ELAPSED of the terrain draw"},
            {"telemetry", summary.toJson()},
            {"total_seconds", std::chrono::duration<double>(Clock::now() - start).count()},
            {"gl", tools::glInfoJson(*context.value())},
        };
        out.update(surfaceFields);
        if (!flown.value().report.is_null()) out.update(flown.value().report);
        std::puts(out.dump(2).c_str());
    }
    fmt::print(
        stderr,
        "terrain-render: {}, {} frames of {}x{} at ε = {} px into {} ({} PNGs): triangles p50 "
        "{:.0f} (max {}), {} patches max, {} draw call(s) per frame, LOD update p50 {:.0f} µs\n",
        kit->tiling(), frames, o.widthPx, o.heightPx, o.errorPx, o.outputDir, framesWritten,
        triangles.percentile(50.0) * 1000.0, maxTriangles, maxPatches, maxDrawCalls,
        lodUs.percentile(50.0) * 1000.0);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{
        "Fly a camera path through a pyramid headless (EGL): streaming, the LOD quadtree and "
        "the tessellated draw of the runtime. Writes PNG frames, a per-frame telemetry CSV "
        "(docs/telemetry.md) and, with --json, a summary."};
    RenderOptions o;
    app.add_option("pyramid", o.pyramid, "Pyramid folder (terrain-build's output)")->required();
    app.add_option(
        "--path", o.pathFile,
        "Camera path JSON (docs/camera-path.md; a globe camera path for a globe pyramid); "
        "default: a path made for the pyramid (on a globe, from orbit to 1 m above "
        "the ground at the data)");
    app.add_option("--save-path", o.savePath, "Write the camera path used to this file");
    app.add_option("--duration-s", o.durationS, "Length of the default path, seconds (20)")
        ->check(tools::positiveNumber());
    app.add_option("-o,--output", o.outputDir, "Folder for frames and telemetry.csv")
        ->capture_default_str();
    tools::addFrameSizeFlags(app, o.widthPx, o.heightPx);
    tools::addErrorPxFlag(app, o.errorPx);
    tools::addMaxSamplePxFlag(app, o.maxSamplePx);
    tools::addMethodFlag(app, o.method);
    app.add_flag("--ripolles-no-coherence", o.ripollesNoCoherence,
                 "ripolles: each frame starts again from the input mesh (the paper's Table 3, "
                 "\"no coherence exploitation\")");
    app.add_option("--fps", o.fps, "Path seconds per frame = 1 / fps")
        ->capture_default_str()
        ->check(CLI::Range(0.01, 1e4));
    app.add_option("--frames", o.frames, "Frames to render (default: the whole path)");
    app.add_option("--every", o.every,
                   "Write every k-th frame as a PNG (0: none; the last is always written)")
        ->capture_default_str();
    app.add_option("--frame", o.frameList, "Also write these frames (repeatable)");
    app.add_flag("--settle", o.settle, "Wait for streaming before drawing each frame");
    tools::addStreamingBudgetFlags(app, o.budgets);
    o.look.addTo(app);
    o.globe.addTo(app);
    app.add_flag("--json", o.json, "Print a JSON summary on stdout");
    if (const auto status = terrain::tools::parseCommandLine(app, argc, argv)) return *status;
    return run(o);
}
