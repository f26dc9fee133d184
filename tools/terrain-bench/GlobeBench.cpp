#include "GlobeBench.h"

#include "GlInfoJson.h"
#include "GlobeFlight.h"
#include "terrain/base/AtomicFile.h"
#include "terrain/build/GlobeSourceSurface.h"
#include "terrain/dem/OpenDem.h"
#include "terrain/gl/Framebuffer.h"
#include "terrain/gl/HeadlessGlContext.h"
#include "terrain/pyramid/GlobeGroundHeight.h"
#include "terrain/pyramid/PyramidReader.h"
#include "terrain/pyramid/VirtualPlanetPyramid.h"
#include "terrain/runtime/FrameImages.h"
#include "terrain/runtime/GlobeCameraPath.h"
#include "terrain/runtime/GlobeReferenceScene.h"
#include "terrain/runtime/GlobeTruth.h"
#include "terrain/runtime/ImageComparison.h"
#include "terrain/runtime/LatencyHistogram.h"
#include "terrain/runtime/ReferenceRenderer.h"
#include "terrain/runtime/ScreenSpaceError.h"
#include "terrain/runtime/TerrainSession.h"
#include "terrain/source/DemReader.h"

#include <epoxy/gl.h>
#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <numbers>
#include <optional>
#include <utility>

namespace terrain::tools {
namespace {

using Clock = std::chrono::steady_clock;
namespace fs = std::filesystem;
constexpr double kDegree = std::numbers::pi / 180.0;
// The background of every frame, LOD and reference alike (space), and its 8-bit value: a
// pixel of it in the LOD image where the reference drew ground is uncovered.
constexpr std::array<float, 4> kSpace{0.02f, 0.03f, 0.08f, 1.0f};
constexpr std::array<std::uint8_t, 3> kSpaceRgb{5, 8, 20};

int fail(const std::string& message) {
    fmt::print(stderr, "terrain-bench: {}\n", message);
    return 1;
}

struct Frame {
    runtime::TerrainDrawStats drawn;
    runtime::LodUpdateStats lod;
    double lodUs = 0.0;
};

// One settled frame of `session` for `camera`, drawn with or without skirts; its depth.
Frame drawFrame(runtime::TerrainSession& session, gl::Framebuffer& framebuffer,
                const runtime::Camera& camera, bool skirts, std::vector<float>& depth) {
    Frame frame;
    session.settle(camera, std::chrono::seconds(60));
    frame.lod = session.beginFrame(camera);
    frame.lodUs = session.lodUpdateUs();
    framebuffer.clear(kSpace, 0.0f);
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer.id());
    glViewport(0, 0, camera.viewportWidth, camera.viewportHeight);
    runtime::TerrainStyle style;
    style.skirts = skirts;
    style.measure = skirts;
    frame.drawn = session.draw(camera, style);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    runtime::FrameTelemetry ignored;
    session.endFrame(ignored);
    depth = framebuffer.readDepth();
    return frame;
}

// Where a frame's worst measured error is: latitude, longitude, drawn and reference heights.
nlohmann::json worstJson(const runtime::ScreenSpaceErrorStats& error) {
    if (error.worstX < 0) return nullptr;
    const globe::Geodetic at = globe::Wgs84::toGeodetic(error.worstWorld);
    return {{"latitude", at.latitudeDeg},
            {"longitude", at.longitudeDeg},
            {"drawn_m", at.height},
            {"reference_m", error.worstReferenceM}};
}

// The reference image of `camera` (ReferenceRenderer, GlobeReferenceScene): colour and depth;
// nothing when the view holds more finest data than the reference draws (kDefaultMaxRegions).
Result<std::optional<runtime::FrameImages>> drawReference(runtime::ReferenceRenderer& reference,
                                                          gl::Framebuffer& framebuffer,
                                                          const runtime::Camera& camera) {
    framebuffer.clear(kSpace, 0.0f);
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer.id());
    glViewport(0, 0, camera.viewportWidth, camera.viewportHeight);
    runtime::ReferenceStyle style;
    style.skyColor = {kSpace[0], kSpace[1], kSpace[2]};
    auto drawn = reference.draw(camera, style);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (!drawn) return drawn.error();
    if (!drawn.value().complete) return std::optional<runtime::FrameImages>();
    runtime::FrameImages images = runtime::readFrameImages(framebuffer);
    images.heightM.clear();  // not compared; keeps the flight's images small
    return std::optional<runtime::FrameImages>(std::move(images));
}

}  // namespace

int runGlobeBench(const GlobeBenchOptions& o) {
    const auto start = Clock::now();
    // Its reference render walks every present patch down to the deepest one in view, which
    // for the virtual planet means generating tens of thousands of patches a frame.
    if (io::isVirtualPlanetName(o.pyramid))
        return fail(o.pyramid +
                    ": the virtual planet is not measured here (its reference render would "
                    "generate every patch of every level in view); build a box of it with "
                    "terrain-build 'planet:level=L,west=…,south=…,east=…,north=…' --globe and "
                    "measure that pyramid with the same name as --source");
    if (o.sources.empty())
        return fail(o.pyramid +
                    ": a globe pyramid is measured against the DEMs it was built from: "
                    "give them with --source");
    std::vector<std::unique_ptr<io::DemReader>> readers;
    std::vector<io::DemReader*> pointers;
    // Opened as the build opened them. A projected source's reference surface is then the
    // longitude/latitude grid it was resampled onto, not its own samples' triangles.
    io::DemOpenOptions sourceOptions = o.sourceOptions;
    sourceOptions.geographicGrid = true;
    for (const std::string& source : o.sources) {
        auto opened = io::openDem({source}, sourceOptions);
        if (!opened) return fail(opened.error().message);
        pointers.push_back(opened.value().get());
        readers.push_back(std::move(opened).value());
    }
    auto manifest = io::readManifest(o.pyramid);
    if (!manifest) return fail(manifest.error().message);
    auto surface = io::GlobeSourceSurface::read(pointers, std::uint64_t{8} << 30,
                                                manifest.value().layout.patchQuads());
    if (!surface) return fail(surface.error().message);
    runtime::GlobeTruth sourceTruth(
        [&surface](double latitude, double longitude) -> Result<std::pair<double, double>> {
            return surface.value().heightsAt(latitude, longitude);
        });
    auto finest = io::GlobeGroundQuery::open(o.pyramid);
    if (!finest) return fail(finest.error().message);
    runtime::GlobeTruth finestTruth([&](double latitude, double longitude) {
        return finest.value().heightsAt(latitude, longitude);
    });
    auto context = gl::HeadlessGlContext::create();
    if (!context) return fail(context.error().message);
    auto framebuffer = gl::Framebuffer::create(o.widthPx, o.heightPx, "globe bench");
    if (!framebuffer) return fail(framebuffer.error().message);
    auto referenceTarget =
        gl::Framebuffer::createWithFloatAttachment(o.widthPx, o.heightPx, "globe bench reference");
    if (!referenceTarget) return fail(referenceTarget.error().message);
    auto pyramid = io::PyramidReader::open(o.pyramid);
    if (!pyramid) return fail(pyramid.error().message);
    auto reference = runtime::ReferenceRenderer::create(
        std::make_unique<runtime::GlobeReferenceScene>(pyramid.value()));
    if (!reference) return fail(reference.error().message);
    // The reference images of the flight's frames (colour and depth, 8 bytes a pixel), drawn
    // once and kept for the other runs, which fly the same cameras, when they fit in
    // kMaxKeptReferenceBytes; else drawn again in every run into two slots, this frame's and
    // the last one's (popping compares the two).
    constexpr std::uint64_t kMaxKeptReferenceBytes = std::uint64_t{2} << 30;
    const bool keepReferences = std::uint64_t(std::max(o.frames, 0)) * std::uint64_t(o.widthPx) *
                                    std::uint64_t(o.heightPx) * 8 <=
                                kMaxKeptReferenceBytes;
    std::vector<std::optional<runtime::FrameImages>> references;
    const io::ManifestGlobe& g = *manifest.value().globe;
    auto path = globeFlight(o.pyramid, o.pathFile, 20.0);
    if (!path) return fail(path.error().message);
    runtime::Camera camera;
    camera.viewportWidth = o.widthPx;
    camera.viewportHeight = o.heightPx;

    nlohmann::json runs = nlohmann::json::array();
    const double comparisonPx =
        std::find(o.thresholdsPx.begin(), o.thresholdsPx.end(), 2.0) != o.thresholdsPx.end()
            ? 2.0
            : o.thresholdsPx.front();
    std::vector<std::pair<double, bool>> plan;
    for (const double t : o.thresholdsPx) plan.push_back({t, true});
    plan.push_back({comparisonPx, false});
    for (const auto& [errorPx, horizonCulling] : plan) {
        runtime::TerrainSessionOptions options;
        o.budgets.applyTo(options.streaming);
        options.lod.errorPx = errorPx;
        options.lod.horizonCulling = horizonCulling;
        auto opened = runtime::TerrainSession::open(o.pyramid, options);
        if (!opened) return fail(opened.error().message);
        runtime::TerrainSession& session = *opened.value();
        runtime::LatencyHistogram lodUs;
        double errorMax = 0.0, errorP99Max = 0.0, lodErrorMax = 0.0;
        double trianglesSum = 0.0, patchesSum = 0.0;
        std::uint64_t trianglesMax = 0, patchesMax = 0, framesOver = 0, lodFramesOver = 0;
        std::uint64_t culled = 0, visited = 0, crackPixels = 0;
        double psnrMin = runtime::kIdenticalPsnrDb, psnrSum = 0.0, poppingSum = 0.0,
               poppingMax = 0.0;
        std::uint64_t compared = 0, poppingFrames = 0;
        nlohmann::json frames = nlohmann::json::array();
        std::vector<float> depth, depthNoSkirts;
        std::vector<std::uint8_t> lodPrevious;
        for (int f = 0; f < o.frames; ++f) {
            const double fraction = o.frames > 1 ? double(f) / double(o.frames - 1) : 1.0;
            path.value().apply(path.value().startS() + fraction * path.value().durationS(), camera);
            const Frame frame = drawFrame(session, framebuffer.value(), camera, true, depth);
            runtime::FrameImages lod;
            lod.width = o.widthPx;
            lod.height = o.heightPx;
            lod.rgba = framebuffer.value().readColorRgba8();
            lod.depth = std::move(depth);
            drawFrame(session, framebuffer.value(), camera, false, depthNoSkirts);
            const auto slotOf = [&](int frameIndex) {
                return static_cast<std::size_t>(keepReferences ? frameIndex : frameIndex % 2);
            };
            const std::size_t slot = slotOf(f);
            if (references.size() <= slot) references.resize(slot + 1);
            if (!keepReferences || !references[slot]) {
                auto drawn = drawReference(reference.value(), referenceTarget.value(), camera);
                if (!drawn) return fail(drawn.error().message);
                references[slot] = std::move(drawn).value();
            }
            const std::optional<runtime::FrameImages>* referencePrevious =
                f > 0 ? &references[slotOf(f - 1)] : nullptr;
            // Frames whose reference was too big to draw are not compared (null in the JSON).
            nlohmann::json psnrJson, cracksJson, poppingJson;
            if (const std::optional<runtime::FrameImages>& truth = references[slot]) {
                const double psnr = runtime::compareImages(lod.rgba, truth->rgba).psnrDb;
                const std::size_t cracks =
                    runtime::countUncoveredPixels(lod, *truth, kSpaceRgb).cracks.size();
                ++compared;
                psnrMin = std::min(psnrMin, psnr);
                psnrSum += psnr;
                crackPixels += cracks;
                psnrJson = psnr;
                cracksJson = cracks;
                if (referencePrevious != nullptr && referencePrevious->has_value()) {
                    const double popping = runtime::poppingLevels(
                        lodPrevious, lod.rgba, (*referencePrevious)->rgba, truth->rgba);
                    ++poppingFrames;
                    poppingSum += popping;
                    poppingMax = std::max(poppingMax, popping);
                    poppingJson = popping;
                }
            }
            lodPrevious = std::move(lod.rgba);
            auto measured = runtime::measureScreenSpaceError(camera, lod.depth, depthNoSkirts, {},
                                                             sourceTruth, errorPx);
            if (!measured) return fail(measured.error().message);
            auto lodMeasured = runtime::measureScreenSpaceError(camera, lod.depth, depthNoSkirts,
                                                                {}, finestTruth, errorPx);
            if (!lodMeasured) return fail(lodMeasured.error().message);
            const runtime::ScreenSpaceErrorStats& error = measured.value();
            const runtime::ScreenSpaceErrorStats& lodError = lodMeasured.value();
            errorMax = std::max(errorMax, error.maxPx);
            errorP99Max = std::max(errorP99Max, error.p99Px);
            lodErrorMax = std::max(lodErrorMax, lodError.maxPx);
            framesOver += error.maxPx > errorPx + o.tolerancePx ? 1 : 0;
            lodFramesOver += lodError.maxPx > errorPx + o.tolerancePx ? 1 : 0;
            trianglesSum += double(frame.drawn.triangles);
            trianglesMax = std::max(trianglesMax, frame.drawn.triangles);
            patchesSum += double(frame.lod.drawn);
            patchesMax = std::max<std::uint64_t>(patchesMax, frame.lod.drawn);
            culled += frame.lod.horizonCulled;
            visited += frame.lod.visited;
            lodUs.add(frame.lodUs / 1000.0);
            frames.push_back({{"frame", f},
                              {"height_m", runtime::globePoseOf(camera).where.height},
                              {"triangles", frame.drawn.triangles},
                              {"patches", frame.lod.drawn},
                              {"horizon_culled", frame.lod.horizonCulled},
                              {"held_splits", frame.lod.heldSplits},
                              {"lod_us", frame.lodUs},
                              {"error_max_px", error.maxPx},
                              {"error_p99_px", error.p99Px},
                              {"pixels_measured", error.pixels},
                              {"worst", worstJson(error)},
                              {"lod_error_max_px", lodError.maxPx},
                              {"lod_worst", worstJson(lodError)},
                              {"psnr_db", psnrJson},
                              {"crack_pixels", cracksJson},
                              {"popping_levels", poppingJson}});
        }
        // Time to full detail after arriving: the last pose, a fresh session, no settling.
        auto fresh = runtime::TerrainSession::open(o.pyramid, options);
        if (!fresh) return fail(fresh.error().message);
        const auto arrived = Clock::now();
        std::uint64_t arrivalFrames = 0;
        bool settled = false;
        while (!settled && std::chrono::duration<double>(Clock::now() - arrived).count() < 120.0) {
            const runtime::LodUpdateStats& lod = fresh.value()->beginFrame(camera);
            framebuffer.value().clear({0.0f, 0.0f, 0.0f, 1.0f}, 0.0f);
            glBindFramebuffer(GL_FRAMEBUFFER, framebuffer.value().id());
            fresh.value()->draw(camera, runtime::TerrainStyle{});
            glBindFramebuffer(GL_FRAMEBUFFER, 0);
            runtime::FrameTelemetry ignored;
            fresh.value()->endFrame(ignored);
            ++arrivalFrames;
            settled = lod.waitingSplits == 0 && fresh.value()->streamer().loadsOutstanding() == 0;
        }
        const double arrivalS = std::chrono::duration<double>(Clock::now() - arrived).count();
        const auto n = static_cast<double>(std::max(o.frames, 1));
        runs.push_back(
            {{"threshold_px", errorPx},
             {"horizon_culling", horizonCulling},
             {"frames", o.frames},
             {"error_max_px", errorMax},
             {"error_p99_max_px", errorP99Max},
             {"frames_over_threshold", framesOver},
             {"lod_error_max_px", lodErrorMax},
             {"lod_frames_over_threshold", lodFramesOver},
             {"frames_compared_with_reference", compared},
             {"psnr_min_db", compared > 0 ? nlohmann::json(psnrMin) : nlohmann::json()},
             {"psnr_mean_db",
              compared > 0 ? nlohmann::json(psnrSum / double(compared)) : nlohmann::json()},
             {"crack_pixels_total", crackPixels},
             {"popping_mean_levels", poppingFrames > 0 ? poppingSum / double(poppingFrames) : 0.0},
             {"popping_max_levels", poppingMax},
             {"triangles_mean", trianglesSum / n},
             {"triangles_max", trianglesMax},
             {"patches_mean", patchesSum / n},
             {"patches_max", patchesMax},
             {"horizon_culled_fraction_of_visited",
              visited > 0 ? double(culled) / double(visited) : 0.0},
             {"lod_us_p50", lodUs.percentile(50.0) * 1000.0},
             {"lod_us_max", lodUs.max() * 1000.0},
             {"full_detail_after_arrival",
              settled ? nlohmann::json{{"frames", arrivalFrames}, {"seconds", arrivalS}}
                      : nlohmann::json()},
             {"per_frame", frames}});
        fmt::print(
            stderr,
            "terrain-bench: globe, ε = {} px, horizon culling {}: measured error against the "
            "sources max {:.3f} px, {} of {} frames over ε + {} px; the LOD's own (against the "
            "finest level) max {:.3f} px, {} frames over; against the reference image PSNR min "
            "{:.1f} dB, {} crack pixels, popping mean {:.2f} levels ({} of {} frames compared); "
            "triangles mean {:.0f}, "
            "patches max {}, horizon-culled {:.1f} % of visited, full detail {} frames after "
            "arriving\n",
            errorPx, horizonCulling ? "on" : "off", errorMax, framesOver, o.frames, o.tolerancePx,
            lodErrorMax, lodFramesOver, psnrMin, crackPixels,
            poppingFrames > 0 ? poppingSum / double(poppingFrames) : 0.0, compared, o.frames,
            trianglesSum / n, patchesMax,
            100.0 * (visited > 0 ? double(culled) / double(visited) : 0.0), arrivalFrames);
    }

    // The same view straight down from 10 km at a pole, on the equator, over a cube edge and
    // over a cube corner (where the data reaches: a regional pyramid draws bare ellipsoid
    // elsewhere).
    nlohmann::json sameView = nlohmann::json::array();
    {
        runtime::TerrainSessionOptions options;
        o.budgets.applyTo(options.streaming);
        options.lod.errorPx = comparisonPx;
        auto opened = runtime::TerrainSession::open(o.pyramid, options);
        if (!opened) return fail(opened.error().message);
        camera.fovY = 50.0 * kDegree;
        for (const auto& [name, lat, lon] :
             {std::tuple{"north pole", 90.0, 0.0}, std::tuple{"south pole", -90.0, 0.0},
              std::tuple{"equator", 0.0, 0.0}, std::tuple{"cube edge", 0.0, 45.0},
              std::tuple{"cube corner", 35.26439, 45.0}}) {
            runtime::placeOnGlobe(camera, {{lat, lon, 10e3}, 0.0, -90.0});
            // Each place's own cut, as a fresh LOD chooses it: not what the tree kept of the
            // place before (a teleport merges what it no longer needs a level a frame).
            opened.value()->restartLod();
            std::vector<float> ignored;
            const Frame frame =
                drawFrame(*opened.value(), framebuffer.value(), camera, true, ignored);
            sameView.push_back(
                {{"place", name},
                 {"patches", frame.lod.drawn},
                 {"data_patches", frame.lod.drawn - frame.lod.drawnBare - frame.lod.drawnVirtual}});
        }
    }

    // Samples stored against a longitude/latitude grid of the same equatorial spacing: the
    // finest face grid's spacing along the equator at a face centre is π/2 / (2^L·(N−1))
    // radians, where a lon/lat grid needs 2π/that × π/that samples (8 faces' worth, not 6).
    std::uint64_t storedSamples = 0;
    const auto tile = static_cast<std::uint64_t>(manifest.value().layout.patchSamples());
    for (const io::ManifestLevel& level : manifest.value().levels)
        storedSamples += static_cast<std::uint64_t>(level.presentPatches) * tile * tile;
    const double faceSamples =
        std::ldexp(double(manifest.value().layout.patchQuads()), g.faceFinestLevel);
    const nlohmann::json storage{
        {"stored_samples_all_levels", storedSamples},
        {"finest_level_samples_whole_globe", 6.0 * faceSamples * faceSamples},
        {"lon_lat_grid_same_equatorial_spacing", 8.0 * faceSamples * faceSamples},
        {"whole_globe_ratio", 6.0 / 8.0}};

    const nlohmann::json out{
        {"tool", "terrain-bench"},
        {"pyramid", o.pyramid},
        {"tiling", "globe"},
        {"sources", o.sources},
        {"width_px", o.widthPx},
        {"height_px", o.heightPx},
        {"flight", o.pathFile.empty()
                       ? nlohmann::json("20,000 km straight down to 1 m above the ground at the "
                                        "centre of the finest data")
                       : nlohmann::json(o.pathFile)},
        {"runs", runs},
        {"same_view_straight_down_10km", sameView},
        {"storage", storage},
        {"command", o.commandLine},
        {"total_seconds", std::chrono::duration<double>(Clock::now() - start).count()},
        {"gl", glInfoJson(*context.value())}};
    std::error_code ec;
    fs::create_directories(o.outputDir, ec);
    const fs::path file = fs::path(o.outputDir) / "globe-bench.json";
    if (Status written = writeAtomically(
            file,
            [&](const fs::path& temporary) -> Status {
                std::ofstream stream(temporary);
                stream << out.dump(2) << "\n";
                return stream ? Status{} : Status{Error{file.string() + ": cannot write"}};
            });
        !written)
        return fail(written.error().message);
    if (o.chart) {
        fs::create_directories(o.reportDir, ec);
        if (ec)
            return fail(fmt::format("{}: cannot create the folder: {}", o.reportDir, ec.message()));
        auto ran = runChartScript(*o.chart, {"--globe-bench", fs::path(o.outputDir).string(),
                                             "--out", o.reportDir, "--report"});
        if (!ran) return fail(ran.error().message);
    }
    if (o.json) std::puts(out.dump(2).c_str());
    return 0;
}

}  // namespace terrain::tools
