// terrain-bench: speed against accuracy (issue 6; docs/accuracy.md), on the plane and on the
// globe alike. Flies a camera path through a pyramid once per LOD method (--methods;
// docs/lod-methods.md) and error threshold ε — one strategy per (method, threshold), so no
// flight inherits another's LOD; on the globe also once without horizon culling — and
// measures every frame: triangles, patches, draw calls, LOD µs, GPU ms, resident bytes, and
// against the truth (BenchTruth: the finest level on the plane, the sources and the finest
// level on the globe) and its reference image (drawn once per frame, shared by every run) the
// measured screen-space error, RMSE/PSNR, cracks and popping. The surface's own figures come
// from its SurfaceKit (the time to full detail after arriving) and GlobeFigures. Writes
// frames.csv, summary.csv, one telemetry CSV per run and bench.json; --report DIR also runs
// the chart tool for PNG charts and report.md.
#include "BenchRecords.h"
#include "BenchTruth.h"
#include "ChartScript.h"
#include "CommandLine.h"
#include "DemOpenFlags.h"
#include "FrameSizeFlags.h"
#include "FullDetailAfterArrival.h"
#include "GlImagePng.h"
#include "GlInfoJson.h"
#include "GlobeFigures.h"
#include "SeamsInView.h"
#include "SeamsJson.h"
#include "StreamingBudgetFlags.h"
#include "StressPoses.h"
#include "SurfaceKit.h"

#include "LodFlags.h"
#include "NumberChecks.h"
#include "terrain/base/AtomicFile.h"
#include "terrain/cache/GpuTilePool.h"
#include "terrain/gl/HeadlessGlContext.h"
#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/pyramid/VirtualPlanetPyramid.h"
#include "terrain/runtime/AccuracyProbe.h"
#include "terrain/runtime/FlightPath.h"
#include "terrain/runtime/ImageComparison.h"
#include "terrain/runtime/ImageryReference.h"
#include "terrain/runtime/ImageryTexelsPerPixel.h"
#include "terrain/runtime/LodStrategyFactory.h"
#include "terrain/runtime/PlaneSurface.h"
#include "terrain/runtime/TelemetryCsvWriter.h"
#include "terrain/runtime/TerrainSession.h"

#include <epoxy/gl.h>
#include <fmt/core.h>
#include <unistd.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;
using namespace terrain;
namespace fs = std::filesystem;

struct BenchOptions {
    std::string pyramid;
    std::string referencePyramid;  ///< the ground truth's pyramid, if not `pyramid`
    std::string methods = "yusov2011";
    std::vector<double> thresholdsPx{0.5, 1.0, 2.0, 4.0, 8.0, 16.0};
    std::string pathFile;
    tools::GlobeFlags globe;  ///< --visit only
    double durationS = 20.0;
    int frames = 48;
    int widthPx = 640;
    int heightPx = 360;
    std::string outputDir;
    std::string reportDir;
    bool noSettle = false;
    int settleTimeoutS = 120;
    bool coarseOnly = false;
    bool blocksOnly = false;
    bool vertexNormals = false;
    double maxSamplePx = runtime::TerrainSessionOptions{}.lod.maxSamplePx;
    bool stability = false;
    bool ripollesNoCoherence = false;
    runtime::ValdetaroParameters valdetaro;
    double tolerancePx = 0.05;
    tools::StreamingBudgets budgets{
        .cpuCacheMiB = 256.0, .gpuLayers = 1024, .uploadMiBPerFrame = 64.0};
    double fogDensity = 0.0;
    int sampleFrame = -1;  // -1: the middle frame
    bool json = false;
    std::string commandLine;
    std::vector<std::string> sources;  ///< globe pyramids: the DEMs it was built from
    tools::DemOpenFlags sourceFlags;
    io::DemOpenOptions sourceOptions;  ///< sourceFlags', once parsed
};

/// The run the globe flies besides the thresholds: horizon culling off, at this ε (2 px, the
/// paper's, when measured; else the first threshold), so that what the culling saves and
/// whether it costs a pixel show side by side.
double horizonComparisonPx(const std::vector<double>& thresholdsPx) {
    return std::find(thresholdsPx.begin(), thresholdsPx.end(), 2.0) != thresholdsPx.end()
               ? 2.0
               : thresholdsPx.front();
}

int fail(const std::string& message) {
    fmt::print(stderr, "terrain-bench: {}\n", message);
    return 1;
}

Status writePng(const runtime::FrameImages& images, const fs::path& path) {
    return tools::writeGlRgbaPng(path, images.width, images.height, images.rgba);
}

/// The draped frame, its reference and their difference × 8 side by side (black where the
/// reference compared nothing).
runtime::FrameImages imageryComparisonPicture(const runtime::FrameImages& drawn,
                                              const runtime::ImageryFrameComparison& c) {
    runtime::FrameImages picture;
    picture.width = 3 * drawn.width;
    picture.height = drawn.height;
    picture.rgba.assign(4 * picture.pixels(), 0);
    const auto w = static_cast<std::size_t>(drawn.width);
    for (std::size_t i = 0; i < drawn.pixels(); ++i) {
        const std::size_t row = 3 * w * (i / w), x = i % w;
        const bool compared = c.referenceRgba[4 * i + 3] != 0;
        for (std::size_t k = 0; k < 3; ++k) {
            const int seen = drawn.rgba[4 * i + k], wanted = c.referenceRgba[4 * i + k];
            picture.rgba[4 * (row + x) + k] = static_cast<std::uint8_t>(seen);
            picture.rgba[4 * (row + w + x) + k] = static_cast<std::uint8_t>(wanted);
            picture.rgba[4 * (row + 2 * w + x) + k] =
                compared ? static_cast<std::uint8_t>(std::min(255, 8 * std::abs(seen - wanted)))
                         : std::uint8_t{0};
        }
        for (std::size_t part = 0; part < 3; ++part)
            picture.rgba[4 * (row + part * w + x) + 3] = 255;
    }
    return picture;
}

std::string thresholdName(double px) { return fmt::format("{}", px); }

/// The method's part of a per-run file name: none for the default method and its draw
/// variants (the names the single-method bench has always written), else "METHOD-".
std::string fileTag(const std::string& methodName) {
    return methodName.starts_with("yusov2011") ? "" : methodName + "-";
}

nlohmann::json summaryJson(const tools::ThresholdSummary& s) {
    const auto v = [](double x) { return std::isnan(x) ? nlohmann::json() : nlohmann::json(x); };
    return {{"method", s.method},
            {"threshold_px", s.thresholdPx},
            {"frames", s.frames},
            {"triangles_mean", v(s.trianglesMean)},
            {"triangles_max", s.trianglesMax},
            {"patches_mean", v(s.patchesMean)},
            {"patches_max", s.patchesMax},
            {"draw_calls_max", s.drawCallsMax},
            {"lod_update_us_mean", v(s.lodUpdateUsMean)},
            {"lod_update_us_p95", v(s.lodUpdateUsP95)},
            {"gpu_ms_mean", v(s.gpuMsMean)},
            {"frame_ms_mean", v(s.frameMsMean)},
            {"resident_bytes_max", s.residentBytesMax},
            {"error_max_px", v(s.errorMaxPx)},
            {"error_max_median_px", v(s.errorMaxMedianPx)},
            {"error_mean_px", v(s.errorMeanPx)},
            {"error_p99_max_px", v(s.errorP99MaxPx)},
            {"frames_over_threshold", s.framesOverThreshold},
            {"lod_error_max_px", v(s.lodErrorMaxPx)},
            {"lod_frames_over_threshold", s.lodFramesOverThreshold},
            {"non_finite_pixels_total", s.nonFinitePixelsTotal},
            {"psnr_db_mean", v(s.psnrDbMean)},
            {"psnr_db_min", v(s.psnrDbMin)},
            {"imagery_psnr_db_mean", v(s.imageryPsnrDbMean)},
            {"imagery_psnr_db_min", v(s.imageryPsnrDbMin)},
            {"imagery_worst_frame", v(s.imageryWorstFrame)},
            {"imagery_max_levels", v(s.imageryMaxLevels)},
            {"imagery_visible_pixels_total", v(s.imageryVisiblePixelsTotal)},
            {"imagery_uncovered_pixels_total", v(s.imageryUncoveredPixelsTotal)},
            {"imagery_texels_per_pixel_median", v(s.imageryTexelsPerPixelMedian)},
            {"imagery_texels_in_range_mean", v(s.imageryTexelsInRangeMean)},
            {"imagery_gpu_texels_per_pixel_p5_median", v(s.imageryGpuTexelsPerPixelP5Median)},
            {"imagery_gpu_texels_per_pixel_median", v(s.imageryGpuTexelsPerPixelMedian)},
            {"imagery_gpu_texels_per_pixel_p95_median", v(s.imageryGpuTexelsPerPixelP95Median)},
            {"imagery_gpu_texels_in_range_mean", v(s.imageryGpuTexelsInRangeMean)},
            {"rmse_mean", v(s.rmseMean)},
            {"crack_pixels_total", s.crackPixelsTotal},
            {"popping_levels_mean", v(s.poppingLevelsMean)},
            {"lod_switch_levels_mean", v(s.lodSwitchLevelsMean)},
            {"lod_switch_jump_share_mean", v(s.lodSwitchJumpShareMean)},
            {"frames_waited", s.framesWaited},
            {"frames_unsettled", s.framesUnsettled},
            {"horizon_culled_fraction", v(s.horizonCulledFraction)},
            {"overdrawn_pixels_total", s.overdrawnPixelsTotal},
            {"boundary_artefact_pixels_total", v(s.boundaryArtefactPixelsTotal)},
            {"boundary_silhouette_pixels_total", v(s.boundarySilhouettePixelsTotal)},
            {"seam_slope_max", v(s.seamSlopeMax)},
            {"frames_seam_over_source_slope", s.framesSeamOverSourceSlope},
            {"shading_seam_levels_max", v(s.shadingSeamLevelsMax)},
            {"shading_seam_levels_mean", v(s.shadingSeamLevelsMean)}};
}

/// One (method, threshold) flight: its own strategy, its telemetry log and its previous
/// frame.
struct ThresholdRun {
    runtime::LodMethod method = runtime::LodMethod::Yusov2011;
    /// As recorded: the method, "-coarse-only" when asked, "-no-horizon-culling" for the
    /// globe's comparison run.
    std::string methodName;
    std::string fileTag;  ///< its part of the telemetry and sample file names
    double thresholdPx = 0.0;
    runtime::TerrainSessionOptions options;  ///< as opened (the arrival opens it afresh)
    std::unique_ptr<runtime::LodStrategy> session;
    std::optional<runtime::TelemetryCsvWriter> telemetry;
    std::optional<runtime::LodCapture> previous;
    std::optional<runtime::Camera> previousCamera;  ///< the previous flight frame's
    int unsettledFrames = 0;  ///< frames streaming did not settle for (not waited for again)
    /// The lowest draped-imagery PSNR so far (its frame's picture is written).
    double imageryWorstPsnrDb = std::numeric_limits<double>::infinity();
};

nlohmann::json methodNames(const std::vector<ThresholdRun>& runs) {
    nlohmann::json names = nlohmann::json::array();
    for (const ThresholdRun& r : runs) {
        if (std::find(names.begin(), names.end(), r.methodName) == names.end())
            names.push_back(r.methodName);
    }
    return names;
}

/// Each flown method's one-line description and whether it bounds the measured error, for
/// the report's "Where each method fails".
nlohmann::json methodInfo(const std::vector<ThresholdRun>& runs) {
    nlohmann::json info = nlohmann::json::object();
    for (const ThresholdRun& r : runs) {
        const runtime::LodMethodInfo& m = runtime::lodMethodInfo(r.method);
        info[std::string(m.name)] = {{"summary", std::string(m.summary)},
                                     {"bounds_error", m.boundsError}};
    }
    return info;
}

int run(const BenchOptions& o, const char* argv0) {
    const auto start = Clock::now();
    if (o.thresholdsPx.empty()) return fail("--thresholds: give at least one threshold");
    auto methods = runtime::parseLodMethods(o.methods);
    if (!methods) return fail("--methods: " + methods.error().message);
    for (const double t : o.thresholdsPx) {
        if (!(t > 0.0) || !std::isfinite(t))
            return fail(fmt::format("--thresholds: {} is not a positive number of pixels", t));
    }
    // Its reference render walks every present patch down to the deepest one in view, which
    // for the virtual planet means generating tens of thousands of patches a frame.
    if (io::isVirtualPlanetName(o.pyramid))
        return fail(o.pyramid +
                    ": the virtual planet is not measured here (its reference render would "
                    "generate every patch of every level in view); build a box of it with "
                    "terrain-build 'planet:level=L,west=…,south=…,east=…,north=…' --globe and "
                    "measure that pyramid with the same name as --source");
    auto manifest = io::readManifest(o.pyramid);
    if (!manifest) return fail(manifest.error().message);
    const std::unique_ptr<tools::SurfaceKit> kit = tools::SurfaceKit::of(manifest.value());
    const bool globe = kit->kind() == runtime::SurfaceKind::Globe;
    for (const runtime::LodMethod method : methods.value()) {
        if (auto supported = kit->supports(o.pyramid, method); !supported)
            return fail(supported.error().message);
    }
    if (Status own = kit->refuseForeignFlags(o.pyramid, o.globe); !own)
        return fail(own.error().message);
    if (globe && o.stability)
        return fail(
            o.pyramid +
            ": a globe pyramid; --stability finds its stress poses in planar pyramids only");
    std::optional<tools::ChartScript> chart;
    if (!o.reportDir.empty()) {
        auto found = tools::findChartScript(argv0);
        if (!found) return fail(found.error().message);
        chart = found.value();
        // Before the flight, not after it: a missing matplotlib fails at once.
        if (auto usable = tools::runChartScript(*chart, {"--check"}); !usable)
            return fail(usable.error().message);
    }
    const fs::path outputDir = !o.outputDir.empty()   ? fs::path(o.outputDir)
                               : !o.reportDir.empty() ? fs::path(o.reportDir)
                                                      : fs::path("out/bench");
    std::error_code ec;
    fs::create_directories(outputDir, ec);
    if (ec)
        return fail(
            fmt::format("{}: cannot create the folder: {}", outputDir.string(), ec.message()));

    auto context = gl::HeadlessGlContext::create();
    if (!context) return fail(context.error().message);
    const gl::GlInfo& gl = context.value()->info();
    const bool llvmpipe = gl.renderer.find("llvmpipe") != std::string::npos;
    const std::string gpuMsSource = llvmpipe ? "llvmpipe-cpu" : "gl-timer-query";

    // The truth first: a globe without its sources fails before any flight is opened.
    auto truth = tools::BenchTruth::open(manifest.value(),
                                         {.pyramid = o.pyramid,
                                          .referencePyramid = o.referencePyramid,
                                          .sources = o.sources,
                                          .sourceOptions = o.sourceOptions,
                                          .probe = {.widthPx = o.widthPx,
                                                    .heightPx = o.heightPx,
                                                    .clearColor = kit->measureBackground()}});
    if (!truth) return fail(truth.error().message);
    runtime::AccuracyProbe& probe = truth.value()->probe();
    // The draped imagery's reference, where the pyramid has imagery (ImageryReference.h).
    std::unique_ptr<runtime::ImageryReference> imageryReference;
    if (!manifest.value().imagery.empty()) {
        auto opened = runtime::ImageryReference::open(o.pyramid, manifest.value());
        if (!opened) return fail(opened.error().message);
        imageryReference = std::move(opened).value();
    }

    std::vector<ThresholdRun> runs;
    const auto openRun = [&](runtime::LodMethod method, double threshold,
                             bool horizonCulling) -> Status {
        runtime::TerrainSessionOptions sessionOptions;
        o.budgets.applyTo(sessionOptions.streaming);
        o.budgets.applyTo(sessionOptions.lod);
        sessionOptions.method = method;
        sessionOptions.lod.errorPx = threshold;
        sessionOptions.lod.horizonCulling = horizonCulling;
        sessionOptions.lod.maxSamplePx = o.maxSamplePx;
        sessionOptions.renderer.fragmentNormals = !o.vertexNormals;
        // The draped frame also reads back the texels per pixel the GPU drew.
        sessionOptions.renderer.imageryTexelsPerPixel = imageryReference != nullptr;
        sessionOptions.valdetaro = o.valdetaro;
        sessionOptions.ripolles.coherence = !o.ripollesNoCoherence;
        auto opened = runtime::openLodStrategy(o.pyramid, sessionOptions);
        if (!opened) return opened.error();
        ThresholdRun r;
        r.method = method;
        r.methodName = std::string(runtime::lodMethodName(method));
        if (o.coarseOnly && method == runtime::LodMethod::Yusov2011)
            r.methodName += "-coarse-only";
        else if (o.blocksOnly && method == runtime::LodMethod::Yusov2011)
            r.methodName += "-blocks-only";
        // The methods the terrain draw (TerrainRenderer) draws: the others shade their own way.
        if (o.vertexNormals &&
            (method == runtime::LodMethod::Yusov2011 || method == runtime::LodMethod::ChunkedLod ||
             method == runtime::LodMethod::Uniform))
            r.methodName += "-vertex-normals";
        r.fileTag = fileTag(r.methodName);
        if (!horizonCulling) {
            r.methodName += "-no-horizon-culling";
            r.fileTag += "no-horizon-culling-";
        }
        r.thresholdPx = threshold;
        r.options = sessionOptions;
        r.session = std::move(opened).value();
        auto csv = runtime::TelemetryCsvWriter::create(
            outputDir / fmt::format("telemetry-{}eps-{}.csv", r.fileTag, thresholdName(threshold)));
        if (!csv) return csv.error();
        r.telemetry.emplace(std::move(csv).value());
        runs.push_back(std::move(r));
        return {};
    };
    for (const runtime::LodMethod method : methods.value()) {
        for (const double threshold : o.thresholdsPx) {
            if (auto opened = openRun(method, threshold, true); !opened)
                return fail(opened.error().message);
        }
    }
    if (globe) {
        if (auto opened = openRun(runs.front().method, horizonComparisonPx(o.thresholdsPx), false);
            !opened)
            return fail(opened.error().message);
    }
    const runtime::Surface& surface = runs.front().session->surface();
    const io::PyramidLayout& layout = manifest.value().layout;

    auto flown = kit->flight(o.pyramid, surface, o.pathFile, o.durationS, o.globe);
    if (!flown) return fail(flown.error().message);
    if (!flown.value().said.empty()) fmt::print(stderr, "terrain-bench: {}\n", flown.value().said);
    const runtime::FlightPath& path = flown.value().path;
    if (auto saved = path.save(outputDir / "camera-path.json"); !saved)
        return fail(saved.error().message);

    runtime::Camera pathCamera;
    pathCamera.viewportWidth = o.widthPx;
    pathCamera.viewportHeight = o.heightPx;
    pathCamera.nearPlane = 0.5;
    const int sampleFrame = o.sampleFrame >= 0 ? o.sampleFrame : o.frames / 2;

    // One settled, measured frame of run r for `camera`: LOD, draw, telemetry and the
    // comparison with `reference`. A frame of the flight (`flight`) writes its telemetry row
    // and measures popping against the run's previous frame; a stress pose does neither.
    const auto measureFrame =
        [&](ThresholdRun& r, const runtime::Camera& camera, std::uint64_t frame, double t,
            const runtime::ReferenceCapture& reference,
            const runtime::ReferenceCapture* previousReference,
            bool flight) -> Result<std::pair<tools::FrameRecord, runtime::LodCapture>> {
        runtime::LodStrategy& session = *r.session;
        runtime::TerrainStyle style;
        style.measure = true;
        style.fogDensityPerM = static_cast<float>(o.fogDensity);
        if (o.coarseOnly) style.fixedTessFactor = layout.blockQuads();
        style.coarseCells = !o.blocksOnly;
        // The terrain's measures compare it with the reference's tint: imagery apart, below.
        style.imagery = false;
        tools::FrameRecord rec;
        rec.method = r.methodName;
        rec.thresholdPx = r.thresholdPx;
        rec.frame = frame;
        rec.pathTimeS = t;
        rec.cameraPosition = camera.position;
        rec.cameraYawDeg = camera.yaw * 180.0 / std::numbers::pi;
        rec.cameraPitchDeg = camera.pitch * 180.0 / std::numbers::pi;
        rec.cameraHeightM = kit->cameraHeightM(camera);

        // The previous frame's LOD, still the session's, drawn from this camera: what the
        // image would be without this frame's switch (FrameRecord::lodSwitchLevels).
        std::optional<runtime::LodCapture> held;
        if (flight && r.previousCamera && r.method == runtime::LodMethod::Yusov2011) {
            runtime::TerrainStyle heldStyle = style;
            heldStyle.measure = false;
            heldStyle.lodCamera = *r.previousCamera;
            held = probe.captureLod(session, camera, heldStyle);
        }
        auto frameStart = Clock::now();
        runtime::FrameTelemetry beforeSettle;
        runtime::LodUpdateStats lodStats = session.beginFrame(camera);
        const runtime::LodUpdateStats first = lodStats;
        rec.lodUpdateUs = session.lodUpdateUs();
        if (!o.noSettle && (first.waitingSplits > 0 || session.loadsOutstanding() > 0)) {
            // Let streaming catch up so the figures are the LOD method's, not the
            // disk's; LOD µs stays the first update's, and the frame's telemetry row counts
            // the streaming of the first update and of settling as well as its own.
            session.endFrame(beforeSettle);
            // A method whose view cannot fit the GPU pool (the uniform grid or a flat grid
            // over a large DEM) never settles: its frames are measured as drawn and marked,
            // and after the first such frame it is not waited for again.
            if (r.unsettledFrames > 0 ||
                !session.settle(camera, std::chrono::seconds(o.settleTimeoutS))) {
                if (const runtime::TileFault* fault = session.fatalFault())
                    return Error{
                        fmt::format("{} ({}): {}", o.pyramid, r.methodName, fault->message)};
                if (r.unsettledFrames++ == 0) {
                    fmt::print(stderr,
                               "terrain-bench: frame {} at ε = {} px ({}): streaming did not "
                               "settle within {} s (its view needs more than the GPU pool "
                               "holds?): its frames are measured as drawn\n",
                               frame, r.thresholdPx, r.methodName, o.settleTimeoutS);
                }
                rec.settled = false;
            }
            rec.waitedForStreaming = true;
            frameStart = Clock::now();
            lodStats = session.beginFrame(camera);
        }
        runtime::LodCapture lod = probe.captureLod(session, camera, style);
        // The same frame draped, unlit and without fog: where its imagery covers a pixel
        // wholly, the pixel is the imagery's colour, which ImageryReference computes.
        std::optional<runtime::FrameImages> draped;
        std::vector<float> drapedTexelsPerPixel;
        if (imageryReference) {
            runtime::TerrainStyle drapedStyle = style;
            drapedStyle.imagery = true;
            drapedStyle.imageryLighting = false;
            drapedStyle.fogDensityPerM = 0.0f;
            drapedStyle.measure = false;
            runtime::TerrainDrawStats drapedStats;
            draped = probe.captureImage(session, camera, drapedStyle, &drapedStats,
                                        &drapedTexelsPerPixel);
            if (drapedStats.imageryLayers == 0) draped.reset();  // a method that drapes none
        }
        runtime::FrameTelemetry telemetry;
        session.endFrame(telemetry);
        runtime::addStreamingCounts(telemetry, beforeSettle);
        rec.frameMs = std::chrono::duration<double, std::milli>(Clock::now() - frameStart).count();
        rec.drawMs = lod.drawMs;
        rec.triangles = lod.draw.triangles;
        rec.gpuMs = lod.draw.gpuMs;
        rec.patches = telemetry.patchesDrawn;
        rec.patchesCulled = lodStats.culled;
        rec.lodNodes = lodStats.nodes;
        rec.horizonCulled = lodStats.horizonCulled;
        rec.lodVisited = lodStats.visited;
        rec.patchesVirtual = lodStats.drawnVirtual;
        rec.patchesBare = lodStats.drawnBare;
        rec.patchesNative = lodStats.drawnNative;
        rec.nativeWindows = lodStats.drawnNativeWindows;
        rec.nativeWindowDepthMax = lodStats.deepestNativeWindow;
        rec.drawCalls = telemetry.drawCalls;
        rec.residentBytes = session.memoryBytes();
        telemetry.frame = frame;
        telemetry.timeS = std::chrono::duration<double>(Clock::now() - start).count();
        telemetry.frameMs = rec.frameMs;
        if (flight) r.telemetry->write(telemetry);

        auto accuracy = probe.compare(camera, lod, reference, r.thresholdPx,
                                      flight && r.previous ? &*r.previous : nullptr,
                                      flight ? previousReference : nullptr);
        if (!accuracy) return accuracy.error();
        const runtime::FrameAccuracy& a = accuracy.value();
        rec.errorMaxPx = a.error.maxPx;
        rec.errorMeanPx = a.error.meanPx;
        rec.errorP99Px = a.error.p99Px;
        rec.errorPixels = a.error.pixels;
        rec.errorOverThresholdPixels = a.error.pixelsOverThreshold;
        rec.errorFixedDiagonalMaxPx = a.error.maxFixedDiagonalPx;
        rec.errorMaxSinglePixelPx = a.error.maxSinglePixelPx;
        rec.errorMaxExactPositionPx = a.error.maxExactPositionPx;
        if (a.lodError) rec.lodErrorMaxPx = a.lodError->maxPx;
        rec.errorWorstX = a.error.worstX;
        rec.errorWorstY = a.error.worstY < 0 ? -1 : o.heightPx - 1 - a.error.worstY;
        rec.errorWorstWorld = a.error.worstWorld;
        rec.skirtPixels = a.error.skirtPixels;
        rec.skirtErrorMaxPx = a.error.skirtMaxPx;
        rec.skirtUnboundedPixels = a.error.skirtUnboundedPixels;
        rec.nonFinitePixels = a.error.nonFinitePixels;
        rec.rmse = a.image.rmse;
        rec.psnrDb = a.image.psnrDb;
        rec.crackPixels = a.crackPixels();
        rec.uncoveredPixels = a.uncoveredPixels;
        rec.overdrawnPixels = a.overdrawnPixels;
        if (a.boundaryArtefactPixels)
            rec.boundaryArtefactPixels = static_cast<double>(*a.boundaryArtefactPixels);
        if (a.boundarySilhouettePixels)
            rec.boundarySilhouettePixels = static_cast<double>(*a.boundarySilhouettePixels);
        const tools::SeamsSeen seams =
            tools::seamsInView(manifest.value(), camera, lod.images.depth);
        rec.seamSlope = seams.seamSlope;
        rec.seamSourceSlopeP99 = seams.sourceSlopeP99;
        if (a.boundaryShading) {
            rec.shadingStepBoundaryLevels = a.boundaryShading->boundaryExcessLevels;
            rec.shadingStepInteriorLevels = a.boundaryShading->interiorExcessLevels;
            rec.shadingSeamLevels = a.boundaryShading->seamLevels();
        }
        if (flight && frame == static_cast<std::uint64_t>(sampleFrame) &&
            (!a.boundaryArtefacts.empty() || !a.cracks.empty())) {
            // Where the boundary artefacts and the cracks are: the sample frame with them in
            // yellow and cyan (the probe clears the plane's background to magenta).
            runtime::FrameImages marked = lod.images;
            constexpr std::array<std::uint8_t, 4> kYellow{255, 255, 0, 255};
            constexpr std::array<std::uint8_t, 4> kCyan{0, 255, 255, 255};
            for (const std::size_t i : a.boundaryArtefacts)
                std::copy(kYellow.begin(), kYellow.end(), marked.rgba.begin() + 4 * i);
            for (const std::size_t i : a.cracks)
                std::copy(kCyan.begin(), kCyan.end(), marked.rgba.begin() + 4 * i);
            const auto file = outputDir / fmt::format("sample-{}eps-{}-artefacts.png", r.fileTag,
                                                      thresholdName(r.thresholdPx));
            if (auto w = writePng(marked, file); !w) return w.error();
        }
        if (draped) {
            auto compared = imageryReference->compare(camera, *draped, style);
            if (!compared) return compared.error();
            const runtime::ImageryFrameComparison& c = compared.value();
            rec.imageryPsnrDb = c.psnrDb;
            rec.imageryMaxLevels = c.maxLevels;
            rec.imageryVisiblePixels = static_cast<double>(c.visiblePixels);
            rec.imageryComparedPixels = static_cast<double>(c.comparedPixels);
            rec.imageryUncoveredPixels = static_cast<double>(c.uncoveredPixels);
            rec.imageryTexelsPerPixel = c.texelsPerPixelP50;
            rec.imageryTexelsInRange = c.texelsPerPixelInRange;
            const runtime::ImageryTexelsPerPixel gpu =
                runtime::summariseTexelsPerPixel(drapedTexelsPerPixel);
            rec.imageryGpuTexelsPerPixelP5 = gpu.p5;
            rec.imageryGpuTexelsPerPixelP50 = gpu.p50;
            rec.imageryGpuTexelsPerPixelP95 = gpu.p95;
            rec.imageryGpuTexelsInRange = gpu.inRange;
            if (flight && c.comparedPixels > 0 && c.psnrDb < r.imageryWorstPsnrDb) {
                // The worst frame so far: drawn, reference, and their difference × 8.
                r.imageryWorstPsnrDb = c.psnrDb;
                const auto file = outputDir / fmt::format("imagery-worst-{}eps-{}.png", r.fileTag,
                                                          thresholdName(r.thresholdPx));
                if (auto w = writePng(imageryComparisonPicture(*draped, c), file); !w)
                    return w.error();
            }
        }
        rec.diagonalUncoveredPixels = a.diagonalUncoveredPixels;
        rec.poppingLevels = a.poppingLevels;
        if (held) {
            const runtime::LodSwitchChange change =
                runtime::lodSwitchChange(held->images, lod.images);
            rec.lodSwitchLevels = change.meanLevels;
            rec.lodSwitchJumpShare = change.jumpShare;
        }
        rec.lodChangeLevels = a.lodChangeLevels;
        rec.referenceChangeLevels = a.referenceChangeLevels;
        rec.referenceTriangles = reference.draw.triangles;
        rec.referenceMs = reference.drawMs;
        if (a.error.pixels == 0 && a.referencePixels > 0) {
            fmt::print(stderr, "terrain-bench: frame {} at ε = {} px ({}): no pixel measured\n",
                       frame, r.thresholdPx, r.methodName);
        }
        return std::pair{rec, std::move(lod)};
    };

    std::vector<tools::FrameRecord> records;
    std::optional<runtime::ReferenceCapture> previousReference;
    const bool progress = isatty(STDERR_FILENO) != 0;
    for (int frame = 0; frame < o.frames; ++frame) {
        const double t =
            path.startS() + (o.frames > 1 ? path.durationS() * frame / (o.frames - 1) : 0.0);
        path.apply(t, pathCamera);
        auto reference =
            probe.renderReference(pathCamera, {.fogDensityPerM = static_cast<float>(o.fogDensity)});
        if (!reference) return fail(reference.error().message);
        if (frame == sampleFrame) {
            if (auto w = writePng(reference.value().images, outputDir / "sample-reference.png"); !w)
                return fail(w.error().message);
        }
        for (ThresholdRun& r : runs) {
            auto measured =
                measureFrame(r, pathCamera, static_cast<std::uint64_t>(frame), t, reference.value(),
                             previousReference ? &*previousReference : nullptr, true);
            if (!measured) return fail(measured.error().message);
            const tools::FrameRecord& rec = measured.value().first;
            runtime::LodCapture& lod = measured.value().second;
            if (frame == sampleFrame) {
                const auto file = outputDir / fmt::format("sample-{}eps-{}.png", r.fileTag,
                                                          thresholdName(r.thresholdPx));
                if (auto w = writePng(lod.images, file); !w) return fail(w.error().message);
            }
            records.push_back(rec);
            r.previous = std::move(lod);
            r.previousCamera = pathCamera;
            if (context.value()->debugLog().errorCount() > 0) {
                return fail("OpenGL reported an error:\n" +
                            context.value()->debugLog().formatErrors());
            }
        }
        previousReference = std::move(reference).value();
        if (progress) fmt::print(stderr, "\rterrain-bench: frame {}/{}", frame + 1, o.frames);
    }
    if (progress) fmt::print(stderr, "\n");

    // --stability: every run at the stress poses found in this pyramid (StressPoses.h), into
    // stability.csv; the report's "Where each method fails at the stress poses" is written
    // from it. No popping here: a pose follows no previous frame.
    std::vector<tools::FrameRecord> stability;
    nlohmann::json stabilityJson = nullptr;
    if (o.stability) {
        auto poses = tools::findStressPoses(o.pyramid, o.widthPx, o.heightPx);
        if (!poses) return fail(poses.error().message);
        stabilityJson = {{"csv", "stability.csv"}, {"poses", nlohmann::json::array()}};
        for (const tools::StressPose& pose : poses.value()) {
            const runtime::Camera& c = pose.camera;
            stabilityJson["poses"].push_back(
                {{"name", pose.name},
                 {"what", pose.what},
                 {"camera_position", {c.position.x, c.position.y, c.position.z}},
                 {"camera_yaw_deg", c.yaw * 180.0 / std::numbers::pi},
                 {"camera_pitch_deg", c.pitch * 180.0 / std::numbers::pi}});
            auto reference =
                probe.renderReference(c, {.fogDensityPerM = static_cast<float>(o.fogDensity)});
            if (!reference) return fail(reference.error().message);
            const auto picture = outputDir / fmt::format("stability-{}-reference.png", pose.name);
            if (auto w = writePng(reference.value().images, picture); !w)
                return fail(w.error().message);
            for (ThresholdRun& r : runs) {
                auto measured =
                    measureFrame(r, c, stability.size(), 0.0, reference.value(), nullptr, false);
                if (!measured) return fail(measured.error().message);
                tools::FrameRecord rec = measured.value().first;
                rec.pose = pose.name;
                stability.push_back(rec);
            }
            if (context.value()->debugLog().errorCount() > 0)
                return fail("OpenGL reported an error:\n" +
                            context.value()->debugLog().formatErrors());
            if (progress)
                fmt::print(stderr, "terrain-bench: stress pose {}: {}\n", pose.name, pose.what);
        }
        if (auto w =
                tools::writeFramesCsv(outputDir / "stability.csv", stability, gpuMsSource, true);
            !w)
            return fail(w.error().message);
    }

    for (ThresholdRun& r : runs) {
        if (auto closed = r.telemetry->close(); !closed) return fail(closed.error().message);
        r.session->drain(std::chrono::seconds(10));
    }

    // Where the flight ends (at the ground on the globe), how long each run's view takes to
    // full detail from nothing loaded, drawn as a user would see it: a teleport there.
    std::vector<nlohmann::json> arrivals(runs.size());
    {
        auto target = gl::Framebuffer::create(o.widthPx, o.heightPx, "terrain-bench arrival");
        if (!target) return fail(target.error().message);
        for (std::size_t i = 0; i < runs.size(); ++i) {
            auto arrival = tools::fullDetailAfterArrival(o.pyramid, runs[i].options, pathCamera,
                                                         target.value(), std::chrono::seconds(120));
            if (!arrival) return fail(arrival.error().message);
            arrivals[i] = std::move(arrival).value();
        }
    }
    nlohmann::json surfaceFigures = nullptr;
    if (globe) {
        runtime::TerrainSessionOptions options = runs.front().options;
        options.lod.errorPx = horizonComparisonPx(o.thresholdsPx);
        options.lod.horizonCulling = true;
        auto figures =
            tools::globeFigures(o.pyramid, manifest.value(), options, o.widthPx, o.heightPx);
        if (!figures) return fail(figures.error().message);
        surfaceFigures = std::move(figures).value();
        surfaceFigures["sources"] = o.sources;
        surfaceFigures["seams"] = tools::seamsJson<nlohmann::json>(manifest.value());
        if (!flown.value().report.is_null()) surfaceFigures.update(flown.value().report);
    }

    const std::vector<tools::ThresholdSummary> summaries = tools::summarise(records, o.tolerancePx);
    if (auto w = tools::writeFramesCsv(outputDir / "frames.csv", records, gpuMsSource); !w)
        return fail(w.error().message);
    if (auto w = tools::writeSummaryCsv(outputDir / "summary.csv", summaries, gpuMsSource); !w)
        return fail(w.error().message);

    nlohmann::json thresholds = nlohmann::json::array();
    for (const tools::ThresholdSummary& s : summaries) {
        nlohmann::json summary = summaryJson(s);
        for (std::size_t i = 0; i < runs.size(); ++i) {
            if (runs[i].methodName == s.method && runs[i].thresholdPx == s.thresholdPx)
                summary["full_detail_after_arrival"] = arrivals[i];
        }
        thresholds.push_back(std::move(summary));
    }
    nlohmann::json out{
        {"tool", "terrain-bench"},
        {"command", o.commandLine},
        {"pyramid", o.pyramid},
        {"tiling", kit->tiling()},
        {"path", o.pathFile.empty() ? nlohmann::json("default") : nlohmann::json(o.pathFile)},
        {"path_duration_s", path.durationS()},
        {"frames", o.frames},
        {"width_px", o.widthPx},
        {"height_px", o.heightPx},
        {"settle", !o.noSettle},
        {"tolerance_px", o.tolerancePx},
        {"max_sample_px", o.maxSamplePx},
        {"methods", methodNames(runs)},
        {"method_info", methodInfo(runs)},
        {"ripolles", {{"coherence", !o.ripollesNoCoherence}}},
        {"valdetaro",
         {{"ham_gain", o.valdetaro.hamGain},
          {"pixels_per_sample_at_d_max", o.valdetaro.pixelsPerSampleAtDMax}}},
        {"output_dir", outputDir.string()},
        {"gpu_ms_source", gpuMsSource},
        {"gpu_ms_note", llvmpipe ? "llvmpipe rasterises on the CPU: gpu_ms is the CPU time of "
                                   "the draw as GL_TIME_ELAPSED reports it, not GPU time"
                                 : "GL_TIME_ELAPSED of the terrain draw"},
        {"thresholds", thresholds},
        {"stability", stabilityJson},
        {"total_seconds", std::chrono::duration<double>(Clock::now() - start).count()},
        {"gl", tools::glInfoJson(*context.value())},
    };
    if (globe) {
        out["globe"] = surfaceFigures;
    } else {
        const runtime::TerrainGeometry& geometry = runtime::planeGeometry(surface);
        out["referencePyramid"] = o.referencePyramid.empty() ? o.pyramid : o.referencePyramid;
        out["raster"] = {
            {"width", layout.rasterWidth()},
            {"height", layout.rasterHeight()},
            {"patch_samples", layout.patchSamples()},
            {"block_quads", layout.blockQuads()},
            {"levels", layout.levelCount()},
            {"sample_spacing_m", {geometry.sampleSpacing().x, geometry.sampleSpacing().y}}};
    }
    if (auto w = writeAtomically(
            outputDir / "bench.json",
            [&](const fs::path& temporary) -> Status {
                std::FILE* file = std::fopen(temporary.c_str(), "w");
                if (file == nullptr)
                    return Error{(outputDir / "bench.json").string() + ": cannot write"};
                const std::string text = out.dump(2) + "\n";
                const bool ok = std::fwrite(text.data(), 1, text.size(), file) == text.size();
                return std::fclose(file) == 0 && ok
                           ? Status{}
                           : Status{Error{(outputDir / "bench.json").string() + ": write failed"}};
            });
        !w) {
        return fail(w.error().message);
    }

    if (chart) {
        fs::create_directories(o.reportDir, ec);
        if (ec)
            return fail(fmt::format("{}: cannot create the folder: {}", o.reportDir, ec.message()));
        auto ran = tools::runChartScript(
            *chart, {"--bench-dir", outputDir.string(), "--out", o.reportDir, "--report"});
        if (!ran) return fail(ran.error().message);
    }
    if (o.json) std::puts(out.dump(2).c_str());
    for (const tools::ThresholdSummary& s : summaries) {
        fmt::print(
            stderr,
            "terrain-bench: {} ε = {:>5} px: triangles {:>9.0f}, measured error max {:.3f} px "
            "(median of frame maxima {:.3f}, mean {:.3f}), PSNR {:.2f} dB, {} of {} frames "
            "over ε + {} px, "
            "{} crack pixels, {} overdrawn, {} boundary-artefact pixels ({} at silhouettes), "
            "shading seam {} levels (max), {} "
            "unmeasurable (non-finite) pixels{}{}\n",
            s.method, s.thresholdPx, s.trianglesMean, s.errorMaxPx, s.errorMaxMedianPx,
            s.errorMeanPx, s.psnrDbMean, s.framesOverThreshold, s.frames, o.tolerancePx,
            s.crackPixelsTotal, s.overdrawnPixelsTotal,
            std::isnan(s.boundaryArtefactPixelsTotal)
                ? std::string("no")
                : fmt::format("{:.0f}", s.boundaryArtefactPixelsTotal),
            std::isnan(s.boundarySilhouettePixelsTotal)
                ? std::string("no")
                : fmt::format("{:.0f}", s.boundarySilhouettePixelsTotal),
            std::isnan(s.shadingSeamLevelsMax) ? std::string("no")
                                               : fmt::format("{:.2f}", s.shadingSeamLevelsMax),
            s.nonFinitePixelsTotal,
            std::isnan(s.lodSwitchLevelsMean)
                ? std::string()
                : fmt::format(", LOD switches {:.4f} levels a frame, {:.4f} % of pixels jumping",
                              s.lodSwitchLevelsMean, 100.0 * s.lodSwitchJumpShareMean),
            std::isnan(s.lodErrorMaxPx)
                ? std::string()
                : fmt::format("; the LOD's own error (against the finest level) max {:.3f} px, "
                              "{} frames over; horizon-culled {:.1f} % of visited",
                              s.lodErrorMaxPx, s.lodFramesOverThreshold,
                              100.0 * s.horizonCulledFraction));
        if (!std::isnan(s.imageryPsnrDbMean)) {
            fmt::print(stderr,
                       "terrain-bench: {} ε = {:>5} px: draped imagery against its reference "
                       "PSNR mean {:.2f} dB, worst {:.2f} dB (frame {:.0f}), {:.0f} pixels over "
                       "{} levels (worst {:.0f}), {:.0f} terrain pixels not wholly covered, texels "
                       "per pixel median {:.2f} ({:.1f} % in 0.5-2); as the GPU drew them median "
                       "{:.2f}, p5 {:.2f}, p95 {:.2f} ({:.1f} % in 0.5-2)\n",
                       s.method, s.thresholdPx, s.imageryPsnrDbMean, s.imageryPsnrDbMin,
                       s.imageryWorstFrame, s.imageryVisiblePixelsTotal,
                       runtime::ImageryFrameComparison::kVisibleLevels, s.imageryMaxLevels,
                       s.imageryUncoveredPixelsTotal, s.imageryTexelsPerPixelMedian,
                       100.0 * s.imageryTexelsInRangeMean, s.imageryGpuTexelsPerPixelMedian,
                       s.imageryGpuTexelsPerPixelP5Median, s.imageryGpuTexelsPerPixelP95Median,
                       100.0 * s.imageryGpuTexelsInRangeMean);
        }
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{
        "Speed against accuracy: fly a camera path through a pyramid at several error thresholds "
        "and measure every frame against the full-resolution reference renderer "
        "(docs/accuracy.md). "
        "Writes frames.csv, summary.csv, telemetry-eps-*.csv and bench.json; --report DIR adds "
        "PNG charts and report.md."};
    BenchOptions o;
    app.add_option("pyramid", o.pyramid, "Pyramid folder (terrain-build's output)")->required();
    app.add_option("--reference", o.referencePyramid,
                   "Pyramid whose finest level is the ground truth (default: the measured one): "
                   "the lossless build of a lossy pyramid (terrain-build --max-error-m), so that "
                   "the error is measured against the source's own samples");
    app.add_option("--thresholds", o.thresholdsPx, "Error thresholds ε in pixels (comma-separated)")
        ->delimiter(',')
        ->capture_default_str();
    app.add_option("--path", o.pathFile,
                   "Camera path JSON (docs/camera-path.md); default: a path made for the pyramid");
    app.add_option("--duration-s", o.durationS, "Length of the default path, seconds")
        ->capture_default_str()
        ->check(tools::positiveNumber());
    o.globe.addVisitTo(app);
    app.add_option("--frames", o.frames, "Frames, evenly spread over the path")
        ->capture_default_str()
        ->check(CLI::Range(1, 100000));
    tools::addFrameSizeFlags(app, o.widthPx, o.heightPx);
    app.add_option(
        "-o,--output", o.outputDir,
        "Folder for the CSVs and bench.json (default: the report folder, else out/bench)");
    app.add_option(
        "--report", o.reportDir,
        "Write PNG charts and report.md into this folder (needs /usr/bin/python3 with matplotlib)");
    app.add_option("--settle-timeout-s", o.settleTimeoutS,
                   "Seconds a frame waits for streaming to settle; a method that does not (its "
                   "view needs more than the GPU pool holds) is then measured as drawn and "
                   "reported, and not waited for again")
        ->capture_default_str()
        ->check(CLI::Range(1, 3600));
    app.add_flag("--no-settle", o.noSettle,
                 "Draw each frame as streaming has it (default: let streaming settle first)");
    app.add_option("--methods,--method", o.methods,
                   "LOD methods to fly, comma-separated, or 'all' (docs/lod-methods.md): " +
                       runtime::lodMethodNames())
        ->capture_default_str();
    app.add_flag("--ripolles-no-coherence", o.ripollesNoCoherence,
                 "ripolles: each frame starts again from the input mesh (the paper's Table 3, "
                 "\"no coherence exploitation\")");
    app.add_option("--valdetaro-gain", o.valdetaro.hamGain,
                   "valdetaro2011: g(HAM) = gain · √HAM_max, its T_max (§5.1)")
        ->capture_default_str()
        ->check(tools::positiveNumber());
    app.add_option("--valdetaro-dmax-px", o.valdetaro.pixelsPerSampleAtDMax,
                   "valdetaro2011: d_max (§5.3) where a DEM sample spans this many pixels")
        ->capture_default_str()
        ->check(tools::positiveNumber());
    app.add_flag("--stability", o.stability,
                 "Also measure every method and threshold at the stress poses found in the "
                 "pyramid (its steepest slope, sharpest peak, a view 1 m above the ground, the "
                 "whole terrain, a no-data edge): stability.csv, and in the report \"Where "
                 "each method fails at the stress poses\"");
    app.add_flag("--coarse-only", o.coarseOnly,
                 "Draw every block at its patch's full resolution (no fine LOD): the coarse LOD's "
                 "own error; method yusov2011-coarse-only");
    app.add_flag("--blocks-only", o.blocksOnly,
                 "Draw every patch as tessellation blocks, never as coarse cells (a distant "
                 "patch's grid of one quad per cell, docs/accuracy.md): what coarse cells save; "
                 "method yusov2011-blocks-only")
        ->excludes("--coarse-only");
    app.add_flag("--vertex-normals", o.vertexNormals,
                 "Shade with normals interpolated between the drawn vertices instead of each "
                 "fragment's from the height texture (docs/accuracy.md, \"Image measures\"): "
                 "what shading independent of the tessellation saves; method suffix "
                 "-vertex-normals");
    tools::addMaxSamplePxFlag(app, o.maxSamplePx);
    app.add_option("--tolerance-px", o.tolerancePx,
                   "Rasterisation tolerance added to ε when counting frames over ε")
        ->capture_default_str();
    tools::addStreamingBudgetFlags(app, o.budgets, " (each threshold's session)");
    app.add_option("--fog", o.fogDensity, "Fog density per metre (0: none)")
        ->capture_default_str()
        ->check(tools::nonNegativeNumber());
    app.add_option("--sample-frame", o.sampleFrame,
                   "Frame written as sample PNGs (default: the middle one)");
    app.add_option("--source", o.sources,
                   "Globe pyramids: the DEMs it was built from, the truth it is measured against "
                   "(docs/globe.md)");
    o.sourceFlags.addTo(app);
    app.add_flag("--json", o.json, "Print the JSON summary on stdout");
    if (const auto status = terrain::tools::parseCommandLine(app, argc, argv)) return *status;
    for (int i = 0; i < argc; ++i) o.commandLine += (i == 0 ? "" : " ") + std::string(argv[i]);
    o.sourceOptions = o.sourceFlags.options();
    return run(o, argv[0]);
}
