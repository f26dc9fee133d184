// terrain-stress: the streaming stress test a user runs against their own pyramid. It flies
// a seeded camera through random teleports, fast low-altitude flight and zoom bursts
// against small caches, renders every frame headless (EGL) so the GPU tile pool is real,
// checks the streaming invariants every frame, and prints throughput, latency percentiles
// and a --json summary. Any violation makes the exit status 1. A globe pyramid is flown over
// the whole planet and checked with the globe LOD's invariants (StressTarget).
#include "CommandLine.h"
#include "FaultPrinter.h"
#include "FrameSizeFlags.h"
#include "GlImagePng.h"
#include "GlInfoJson.h"
#include "LodFlags.h"
#include "StreamingBudgetFlags.h"
#include "StressChecks.h"
#include "StressTarget.h"

#include "terrain/base/PeakMemory.h"
#include "terrain/base/ProcessResources.h"
#include "terrain/gl/Framebuffer.h"
#include "terrain/gl/HeadlessGlContext.h"
#include "terrain/pyramid/PyramidReader.h"
#include "terrain/runtime/TelemetryCsvWriter.h"
#include "terrain/runtime/TelemetrySummary.h"

#include <epoxy/gl.h>
#include <fmt/core.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;
using namespace terrain;

struct StressOptions {
    std::string pyramid;
    tools::StreamingBudgets budgets{.cpuCacheMiB = 8.0, .gpuLayers = 64, .uploadMiBPerFrame = 2.0};
    double faultRate = 0.0;
    double latencyMs = 0.0;
    double durationS = 30.0;
    std::uint64_t frames = 0;
    std::uint64_t seed = 1;
    int widthPx = 320;
    int heightPx = 240;
    double errorPx = 2.0;
    std::string method = "yusov2011";
    double fovDegrees = 60.0;
    int tessFactor = 2;
    double warmupS = 5.0;
    std::optional<double> maxRssGrowthPercent;
    std::string flight = "stress";
    double cruiseSpeedMps = 100.0;
    double cruiseAltitudeM = 300.0;
    std::string telemetryCsv;
    std::string framesDir;
    std::uint64_t frameEvery = 100;
    bool colorByLevel = false;
    bool json = false;
};

int fail(const std::string& message) {
    fmt::print(stderr, "terrain-stress: {}\n", message);
    return 1;
}

struct ResidentMemoryTrend {
    std::size_t samples = 0;
    double baselineBytes = 0.0;  ///< median of the first quarter of the samples (≤ 60)
    double endBytes = 0.0;       ///< median of the last quarter (≤ 60)
    double minBytes = 0.0;
    double maxBytes = 0.0;
    double growthPercent = 0.0;
    double slopeBytesPerMinute = 0.0;  ///< least squares over all samples
};

double median(std::vector<double> values) {
    std::sort(values.begin(), values.end());
    return values.empty() ? 0.0 : values[values.size() / 2];
}

/// `samples`: resident bytes once a second.
ResidentMemoryTrend residentMemoryTrend(const std::vector<double>& samples) {
    ResidentMemoryTrend t;
    t.samples = samples.size();
    if (samples.size() < 2) return t;
    const std::size_t window = std::clamp<std::size_t>(samples.size() / 4, 1, 60);
    t.baselineBytes =
        median({samples.begin(), samples.begin() + static_cast<std::ptrdiff_t>(window)});
    t.endBytes = median({samples.end() - static_cast<std::ptrdiff_t>(window), samples.end()});
    t.minBytes = *std::min_element(samples.begin(), samples.end());
    t.maxBytes = *std::max_element(samples.begin(), samples.end());
    t.growthPercent = 100.0 * (t.endBytes - t.baselineBytes) / t.baselineBytes;
    const double n = static_cast<double>(samples.size());
    double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
    for (std::size_t i = 0; i < samples.size(); ++i) {
        const double x = static_cast<double>(i);
        sx += x;
        sy += samples[i];
        sxx += x * x;
        sxy += x * samples[i];
    }
    t.slopeBytesPerMinute = 60.0 * (n * sxy - sx * sy) / (n * sxx - sx * sx);
    return t;
}

nlohmann::json percentilesJson(const runtime::LatencyHistogram& h) {
    const auto value = [](double v) {
        return std::isnan(v) ? nlohmann::json() : nlohmann::json(v);
    };
    return {{"count", h.count()},
            {"p50", value(h.percentile(50.0))},
            {"p95", value(h.percentile(95.0))},
            {"p99", value(h.percentile(99.0))},
            {"max", value(h.max())}};
}

/// Frame `frame` as <framesDir>/frame-NNNNNN.png (top row first).
int run(const StressOptions& o) {
    const auto start = Clock::now();
    auto context = gl::HeadlessGlContext::create();
    if (!context) return fail(context.error().message);

    // The runtime's own frame: streaming, the LOD (which pins what it holds in the small
    // pool and splits only into resident children), one draw; and the flight over it.
    tools::StressTargetOptions targetOptions;
    targetOptions.pyramid = o.pyramid;
    o.budgets.applyTo(targetOptions.streaming);
    o.budgets.applyTo(targetOptions.lod);
    targetOptions.streaming.io.faults = {
        .errorRate = o.faultRate, .addedLatencyMs = o.latencyMs, .seed = o.seed};
    targetOptions.lod.errorPx = o.errorPx;
    auto method = runtime::parseLodMethod(o.method);
    if (!method) return fail("--method: " + method.error().message);
    targetOptions.method = method.value();
    targetOptions.seed = o.seed;
    if (o.flight == "cruise")
        targetOptions.cruiseSpeedAndAltitude = {o.cruiseSpeedMps, o.cruiseAltitudeM};
    auto opened = tools::StressTarget::open(targetOptions);
    if (!opened) return fail(opened.error().message);
    tools::StressTarget& target = *opened.value();
    runtime::TileStreamer& streamer = target.streamer();

    auto framebuffer = gl::Framebuffer::create(o.widthPx, o.heightPx, "stress frame");
    if (!framebuffer) return fail(framebuffer.error().message);
    std::optional<runtime::TelemetryCsvWriter> csv;
    if (!o.telemetryCsv.empty()) {
        auto created = runtime::TelemetryCsvWriter::create(o.telemetryCsv);
        if (!created) return fail(created.error().message);
        csv.emplace(std::move(created).value());
    }

    runtime::Camera camera;
    camera.viewportWidth = o.widthPx;
    camera.viewportHeight = o.heightPx;
    camera.fovY = o.fovDegrees * std::numbers::pi / 180.0;
    runtime::TerrainStyle style;
    style.fixedTessFactor = o.tessFactor;
    style.fogDensityPerM = 0.0f;
    style.debugView =
        o.colorByLevel ? runtime::TerrainDebugView::Level : runtime::TerrainDebugView::Shaded;
    if (!o.framesDir.empty()) {
        std::error_code ec;
        std::filesystem::create_directories(o.framesDir, ec);
        if (ec)
            return fail(fmt::format("{}: cannot create the folder: {}", o.framesDir, ec.message()));
    }

    // Load latencies once warmed up (the cold start fills an empty view at once), in
    // milliseconds and in frames; frames do not depend on how fast this machine renders.
    runtime::LatencyHistogram steadyLatencyMs, steadyLatencyFrames;
    bool warm = false;
    streamer.setLoadObserver([&](const runtime::TileLoad& load) {
        if (!warm) return;
        steadyLatencyMs.add(load.latencyMs);
        steadyLatencyFrames.add(static_cast<double>(load.latencyFrames));
    });
    tools::StressChecks checks;
    runtime::TelemetrySummary summary;
    std::vector<std::string> violations;
    std::uint64_t violationCount = 0;
    const auto violation = [&](std::uint64_t frame, const std::string& what) {
        ++violationCount;
        if (violations.size() < 20) {
            violations.push_back(fmt::format("frame {}: {}", frame, what));
            fmt::print(stderr, "terrain-stress: VIOLATION at frame {}: {}\n", frame, what);
        }
    };
    tools::FaultPrinter faultPrinter("terrain-stress");
    constexpr std::size_t kFaultsInJson = 10;
    // The shard LRU of each reader (the I/O thread's, the ground lookups'), plus slack.
    constexpr std::uint64_t kFdGrowthAllowed = 2 * io::PyramidReader::kDefaultOpenShards + 4;

    // Resident memory once a second after warm-up (reading /proc allocates, so not every
    // frame); the growth compares the medians of the first and the last quarter of the
    // samples (at most a minute each), so one noisy sample cannot pass or fail a run.
    std::vector<double> rssSamples;
    rssSamples.reserve(static_cast<std::size_t>(std::min(o.durationS, 1e6)) + 16);
    // Descriptors and threads, sampled with the memory: at the first sample after warm-up
    // and their most since. Shards open lazily up to each reader's LRU, so descriptors may
    // grow by that much after warm-up and no more; threads not at all.
    std::optional<std::uint64_t> fdsAtWarmup, threadsAtWarmup;
    std::uint64_t fdsMost = 0, threadsMost = 0;
    double nextRssSampleS = o.warmupS;
    const std::array<float, 4> sky{style.skyColor[0], style.skyColor[1], style.skyColor[2], 1.0f};
    const auto loopStart = Clock::now();
    auto previous = loopStart;
    double lastFrameS = 0.0;
    std::uint64_t frame = 0;
    for (;; ++frame) {
        const double elapsedS = std::chrono::duration<double>(Clock::now() - loopStart).count();
        if (o.frames > 0 ? frame >= o.frames : elapsedS >= o.durationS) break;

        // Motion by the last frame's duration (capped), as a real-time viewer moves.
        target.beginFrame(std::min(0.1, lastFrameS), camera);

        framebuffer.value().clear(sky, 0.0f);  // reversed Z: far is 0
        glBindFramebuffer(GL_FRAMEBUFFER, framebuffer.value().id());
        glViewport(0, 0, o.widthPx, o.heightPx);
        target.draw(camera, style);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        if (!o.framesDir.empty() && frame % o.frameEvery == 0) {
            const std::filesystem::path file =
                std::filesystem::path(o.framesDir) / fmt::format("frame-{:06}.png", frame);
            if (auto written = tools::writeFramebufferPng(framebuffer.value(), file); !written) {
                return fail(written.error().message);
            }
        }

        runtime::FrameTelemetry t;
        target.endFrame(t);
        glFinish();  // a frame ends when it is drawn, as a swap would make it
        if (auto broken = target.check(checks)) violation(frame, *broken);

        const auto now = Clock::now();
        t.frame = frame;
        t.timeS = std::chrono::duration<double>(now - loopStart).count();
        t.frameMs = std::chrono::duration<double, std::milli>(now - previous).count();
        lastFrameS = t.frameMs / 1000.0;
        previous = now;
        summary.add(t);
        if (csv) csv->write(t);

        faultPrinter.printNew(streamer);
        warm = t.timeS >= o.warmupS;
        if (t.timeS >= nextRssSampleS) {
            // Sampled once a second after warm-up: reading /proc allocates.
            rssSamples.push_back(static_cast<double>(currentResidentBytes()));
            const std::uint64_t fds = openFileDescriptors(), threads = threadCount();
            if (!fdsAtWarmup) fdsAtWarmup = fds, threadsAtWarmup = threads;
            fdsMost = std::max(fdsMost, fds);
            threadsMost = std::max(threadsMost, threads);
            nextRssSampleS = t.timeS + 1.0;
        }
        if (context.value()->debugLog().errorCount() > 0) {
            violation(frame, "OpenGL reported an error (see the debug log)");
            break;
        }
    }
    const double loopS = std::chrono::duration<double>(Clock::now() - loopStart).count();

    if (!streamer.drain(std::chrono::seconds(30)))
        violation(frame, "requests did not end within 30 s of cancelling them all");
    if (auto broken = tools::StressChecks::afterDrain(streamer)) violation(frame, *broken);
    if (fdsAtWarmup && fdsMost > *fdsAtWarmup + kFdGrowthAllowed)
        violation(frame, fmt::format("open file descriptors grew from {} at warm-up to {} (at "
                                     "most {} more: the shard readers' LRU)",
                                     *fdsAtWarmup, fdsMost, kFdGrowthAllowed));
    if (threadsAtWarmup && threadsMost > *threadsAtWarmup)
        violation(frame, fmt::format("threads grew from {} at warm-up to {}", *threadsAtWarmup,
                                     threadsMost));
    // Every GPU layer comes back: once the LOD lets go nothing stays pinned, and releasing
    // what is resident returns the whole pool to the free list.
    target.releaseLod();
    if (auto broken = tools::StressChecks::afterLodReleased(streamer)) violation(frame, *broken);
    const int released = streamer.releaseAllLayers();
    if (auto broken = tools::StressChecks::afterLayersReleased(streamer, released))
        violation(frame, *broken);
    if (auto broken = streamer.checkInvariants()) violation(frame, *broken);
    if (csv) {
        if (auto closed = csv->close(); !closed) return fail(closed.error().message);
    }
    summary.mergeLoadLatencies(streamer.loadLatencies());

    const ResidentMemoryTrend rss = residentMemoryTrend(rssSamples);
    const double growthPercent = rss.growthPercent;
    if (o.maxRssGrowthPercent && rss.samples >= 8 && growthPercent > *o.maxRssGrowthPercent) {
        violation(frame, fmt::format("resident memory grew {:.2f}% after warm-up (limit {}%)",
                                     growthPercent, *o.maxRssGrowthPercent));
    }

    const std::uint64_t teleports = target.teleports();
    const runtime::TileRequestLedger& ledger = streamer.ledger();
    const io::IoThreadStats io = streamer.ioStats();
    const runtime::LatencyHistogram& latency = streamer.loadLatencies();
    const double tilesPerS = loopS > 0.0 ? static_cast<double>(ledger.completed) / loopS : 0.0;
    if (o.json) {
        nlohmann::json faults = nlohmann::json::array();
        for (std::size_t i = 0; i < streamer.faults().size() && i < kFaultsInJson; ++i) {
            const runtime::TileFault& f = streamer.faults()[i];
            faults.push_back(
                {{"level", f.id.level}, {"x", f.id.x}, {"y", f.id.y}, {"message", f.message}});
        }
        const nlohmann::json out{
            {"tool", "terrain-stress"},
            {"pyramid", o.pyramid},
            {"passed", violationCount == 0},
            {"config",
             {{"cpu_cache_mib", o.budgets.cpuCacheMiB},
              {"gpu_layers", streamer.pool().capacity()},
              {"upload_mib_per_frame", o.budgets.uploadMiBPerFrame},
              {"fault_rate", o.faultRate},
              {"added_latency_ms", o.latencyMs},
              {"seed", o.seed},
              {"width_px", o.widthPx},
              {"height_px", o.heightPx},
              {"error_px", o.errorPx},
              {"method", o.method}}},
            {"frames", frame},
            {"duration_s", loopS},
            {"tiling", target.tiling()},
            {"flight", o.flight},
            {"teleports", teleports},
            {"throughput_tiles_per_s", tilesPerS},
            {"load_latency_ms", percentilesJson(latency)},
            {"after_warmup",
             {{"load_latency_ms", percentilesJson(steadyLatencyMs)},
              {"load_latency_frames", percentilesJson(steadyLatencyFrames)}}},
            {"requests",
             {{"made", ledger.submitted},
              {"completed", ledger.completed},
              {"cancelled", ledger.cancelled},
              {"failed", ledger.failed},
              {"injected_faults", io.injectedFaults}}},
            {"faults", {{"count", streamer.faults().size()}, {"first", faults}}},
            {"invariant_violations", violationCount},
            {"violations", violations},
            {"resident_memory",
             {{"samples", rss.samples},
              {"baseline_bytes", rss.baselineBytes},
              {"end_bytes", rss.endBytes},
              {"min_bytes", rss.minBytes},
              {"max_bytes", rss.maxBytes},
              {"growth_after_warmup_percent", growthPercent},
              {"slope_bytes_per_minute", rss.slopeBytesPerMinute},
              {"peak_bytes", peakResidentBytes()}}},
            {"resources",
             {{"fds_at_warmup", fdsAtWarmup.value_or(0)},
              {"fds_most", fdsMost},
              {"threads_at_warmup", threadsAtWarmup.value_or(0)},
              {"threads_most", threadsMost},
              {"gpu_layers_released_at_exit", released},
              {"gpu_layers_free_at_exit", streamer.pool().layersFree()}}},
            {"telemetry", summary.toJson()},
            {"telemetry_csv",
             o.telemetryCsv.empty() ? nlohmann::json() : nlohmann::json(o.telemetryCsv)},
            {"total_seconds", std::chrono::duration<double>(Clock::now() - start).count()},
            {"gl", tools::glInfoJson(*context.value())},
        };
        std::puts(out.dump(2).c_str());
    }
    fmt::print(
        stderr,
        "terrain-stress: {} frames in {:.1f} s, {} teleports; {} tiles loaded ({:.0f} tiles/s), "
        "{} cancelled, {} failed; load latency p50 {:.1f} ms, p95 {:.1f} ms, p99 {:.1f} ms "
        "(after warm-up p99 {:.1f} ms, {:.0f} frames); "
        "resident memory {:+.2f}% after warm-up; {} invariant violations\n",
        frame, loopS, teleports, ledger.completed, tilesPerS, ledger.cancelled, ledger.failed,
        latency.percentile(50.0), latency.percentile(95.0), latency.percentile(99.0),
        steadyLatencyMs.percentile(99.0), steadyLatencyFrames.percentile(99.0), growthPercent,
        violationCount);
    faultPrinter.printRest(streamer);
    return violationCount == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{
        "Streaming stress test of a pyramid: a seeded flight of random teleports, fast "
        "low-altitude flight and zoom bursts against small CPU and GPU caches, rendered "
        "headless, with the streaming invariants checked every frame. Exit status 1 on any "
        "violation."};
    StressOptions o;
    app.add_option("pyramid", o.pyramid, "Pyramid folder (terrain-build's output)")->required();
    tools::addStreamingBudgetFlags(app, o.budgets);
    app.add_option("--fault-rate", o.faultRate, "Probability that a tile read fails (injected)")
        ->capture_default_str()
        ->check(CLI::Range(0.0, 1.0));
    app.add_option("--latency-ms", o.latencyMs, "Latency added to every tile read, ms")
        ->capture_default_str()
        ->check(CLI::Range(0.0, 1e5));
    app.add_option("--duration-s", o.durationS, "How long to fly, seconds")
        ->capture_default_str()
        ->check(CLI::Range(0.0, 1e7));
    app.add_option("--frames", o.frames,
                   "Stop after this many frames instead (0: use --duration-s)")
        ->capture_default_str();
    app.add_option("--seed", o.seed, "Seed of the flight and of the injected faults")
        ->capture_default_str();
    tools::addFrameSizeFlags(app, o.widthPx, o.heightPx);
    tools::addErrorPxFlag(app, o.errorPx);
    tools::addMethodFlag(app, o.method, " (not rtin, lee2011 or ripolles: they stream nothing)");
    app.add_option("--fov", o.fovDegrees, "Vertical field of view, degrees")
        ->capture_default_str()
        ->check(CLI::Range(5.0, 150.0));
    app.add_option("--tess-factor", o.tessFactor,
                   "Segments per tessellation-block edge (power of two)")
        ->capture_default_str()
        ->check(CLI::Range(1, 64));
    app.add_option("--warmup-s", o.warmupS,
                   "Seconds of warm-up: then the resident-memory baseline is taken and "
                   "after-warm-up latencies start")
        ->capture_default_str()
        ->check(CLI::Range(0.0, 1e6));
    app.add_option("--max-rss-growth-percent", o.maxRssGrowthPercent,
                   "Fail when resident memory grows more than this after warm-up");
    app.add_option("--flight", o.flight,
                   "stress: teleports, low flight and zoom bursts; cruise: a steady flight at "
                   "--speed-mps, --altitude-m above the ground (for latency measurements)")
        ->capture_default_str()
        ->check(CLI::IsMember({"stress", "cruise"}));
    app.add_option("--speed-mps", o.cruiseSpeedMps, "Cruise speed, m/s")
        ->capture_default_str()
        ->check(CLI::Range(0.0, 1e6));
    app.add_option("--altitude-m", o.cruiseAltitudeM, "Cruise altitude above the ground, m")
        ->capture_default_str()
        ->check(CLI::Range(0.0, 1e7));
    app.add_option("--telemetry", o.telemetryCsv, "Write the per-frame cache telemetry CSV here");
    app.add_option("--frames-dir", o.framesDir, "Write every --frame-every-th frame as a PNG here");
    app.add_option("--frame-every", o.frameEvery, "Frames between two PNGs")
        ->capture_default_str()
        ->check(CLI::Range(std::uint64_t{1}, std::uint64_t{1} << 40));
    app.add_flag("--color-by-level", o.colorByLevel, "Colour patches by level in the PNGs");
    app.add_flag("--json", o.json, "Print a JSON summary on stdout");
    if (const auto status = terrain::tools::parseCommandLine(app, argc, argv)) return *status;
    return run(o);
}
