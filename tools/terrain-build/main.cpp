// terrain-build: any DEM (or several as a mosaic, or the procedural source) → a tiled
// on-disk pyramid with guaranteed error bounds (docs/pyramid-format.md). Streaming: peak
// memory stays under --memory whatever the input size.
#include "CommandLine.h"
#include "DemOpenFlags.h"
#include "NoDataSourcesJson.h"
#include "SeamsJson.h"

#include "terrain/dem/OpenDem.h"
#include "terrain/base/PeakMemory.h"
#include "terrain/source/DemReader.h"
#include "terrain/source/DemSlope.h"
#include "terrain/build/PyramidBuilder.h"
#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/build/PyramidShards.h"

#include <fmt/core.h>
#include <unistd.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

namespace {

std::atomic<bool> g_interrupted{false};

extern "C" void onInterrupt(int) { g_interrupted.store(true); }

// "1GiB", "512MiB", "64M", "1073741824" → bytes.

std::optional<std::uint64_t> parseBytes(const std::string& text) {
    std::size_t end = 0;
    double value = 0.0;
    try {
        value = std::stod(text, &end);
    } catch (...) {
        return std::nullopt;
    }
    const std::string unit = text.substr(end);
    double scale = 1.0;
    if (unit.empty() || unit == "B")
        scale = 1.0;
    else if (unit == "K" || unit == "KiB")
        scale = 1024.0;
    else if (unit == "M" || unit == "MiB")
        scale = 1024.0 * 1024.0;
    else if (unit == "G" || unit == "GiB")
        scale = 1024.0 * 1024.0 * 1024.0;
    else
        return std::nullopt;
    if (value <= 0.0) return std::nullopt;
    return static_cast<std::uint64_t>(value * scale);
}

// A one-line progress bar with an ETA, redrawn in place on a terminal.
class ProgressBar {
public:
    void update(const terrain::io::PyramidBuildProgress& p) {
        const double elapsed = std::chrono::duration<double>(Clock::now() - m_start).count();
        if (elapsed - m_lastDrawn < 0.2 && p.fraction < 1.0) return;
        m_lastDrawn = elapsed;
        const int width = 30, filled = static_cast<int>(p.fraction * width);
        const double eta = p.fraction > 0.01 ? elapsed * (1.0 - p.fraction) / p.fraction : 0.0;
        fmt::print(stderr, "\r[{}{}] {:5.1f}%  level {:2}  {:.0f}s elapsed, ETA {:.0f}s ",
                   std::string(filled, '#'), std::string(width - filled, '.'), 100.0 * p.fraction,
                   p.level, elapsed, eta);
    }
    void finish() { fmt::print(stderr, "\n"); }

private:
    using Clock = std::chrono::steady_clock;
    Clock::time_point m_start = Clock::now();
    double m_lastDrawn = -1.0;
};

}  // namespace

int main(int argc, char** argv) {
    using namespace terrain;
    CLI::App app{
        "Build a tiled on-disk terrain pyramid with guaranteed error bounds from a DEM: "
        "GeoTIFF/TIFF, 16-bit PNG, OpenEXR, SRTM .hgt, anything GDAL reads (netCDF, VRT, "
        "DTED, ...), several tiles as a mosaic, or \"procedural:size=16385,seed=1\"."};
    std::vector<std::string> inputs;
    std::string output;
    std::string memory = "1GiB";
    io::PyramidBuildOptions options;
    tools::DemOpenFlags demFlags;
    bool json = false, quiet = false, globe = false;
    app.add_option("INPUT", inputs, "DEM file(s); several files form a mosaic")->required();
    app.add_option("-o,--output", output, "Pyramid folder to create")->required();
    app.add_option("--memory", memory, "Peak memory budget, e.g. 1GiB, 512MiB")
        ->capture_default_str();
    app.add_option("--patch-size", options.patchSamples, "Samples per patch side, 2^n + 1")
        ->capture_default_str();
    app.add_option("--block-quads", options.blockQuads,
                   "Quads per tessellation-block side (8: 16 x 16 blocks in a 129 patch)")
        ->capture_default_str();
    app.add_option("--shard-patches", options.shardPatches, "Patches per shard side")
        ->capture_default_str();
    app.add_option("--compression-level", options.compressionLevel,
                   "Patch compression, lossless: 1..19 zstd level of the height codes and "
                   "bounds; 0 stores them uncompressed, as large as floats")
        ->capture_default_str()
        ->check(CLI::Range(0, 19));
    app.add_option("--max-error-m", options.maxErrorM,
                   "Lossy storage: each finest-level height within this many metres of the "
                   "source, level l's within 2^(finest - l) times it (Yusov 2011, section 4), "
                   "and added to the error bounds; 0 is lossless. Planar pyramids")
        ->capture_default_str();
    bool independentPatches = false;
    app.add_flag("--independent-patches", independentPatches,
                 "Code every patch on its own, not from its parent's samples: each decodes "
                 "without its parent, and the pyramid is larger. Planar pyramids");
    app.add_option("--threads", options.threads, "Worker threads (0: one per core)")
        ->capture_default_str();
    demFlags.addTo(app);
    app.add_flag(
        "--globe", globe,
        "Build a globe pyramid: the sources resampled onto the WGS84 cube-sphere, instead of "
        "a planar sheet around the centre (projected ones, e.g. UTM, first onto a "
        "longitude/latitude grid by GDAL's warper, the bounds still made against their own "
        "samples); several inputs composite there, the finest valid sample winning");
    auto* seaLevelOption =
        app.add_option("--sea-level", options.globeSeaLevelM,
                       "Globe pyramids: the sea's height in the sources' vertical datum, metres "
                       "(default 0: mean sea level, as SRTM, ETOPO and GEBCO state heights); what "
                       "lies at or below it is drawn as water. For sources whose zero is not the "
                       "sea, such as heights above the ellipsoid. Region builds take it at the "
                       "merge");
    auto* oversampleOption =
        app.add_option(
               "--oversample-levels", options.globeOversampleLevels,
               "Globe pyramids: face levels built below each source's own spacing. The finest "
               "level resamples the sources, and its distance from their own triangles is the "
               "floor of the error seen near the ground; each level about halves it, for 4x the "
               "finest level's samples (docs/globe.md, \"Oversampled finest levels\")")
            ->check(CLI::Range(0, io::kMaxGlobeOversampleLevels))
            ->capture_default_str();
    auto* nativeFlag = app.add_flag(
        "--native-leaves", options.globeNativeLeaves,
        "Globe pyramids: also store each longitude/latitude source's own samples (as the "
        "composite shows them) on its own grid, the data of native leaves, which draw the "
        "finest detail at the sources' samples instead of the face grid's resampling "
        "(docs/globe.md, \"Native leaves\"; a region build's --merge builds them)");
    app.add_option("--measured-levels", options.globeMeasuredLevels,
                   "Globe region builds: the levels above the finest whose error bounds are "
                   "measured at the source's samples (each a pass over the source) before the "
                   "nested bound, looser, takes over (default: 2, and every level of a shard "
                   "whose surroundings hold at most 2^24 samples)")
        ->check(CLI::Range(0, 40));
    app.add_flag("--overwrite", options.overwrite, "Replace an existing pyramid");
    // Region builds (docs/pyramid-format.md, "Region builds"): tools/cluster runs these.
    bool plan = false, merge = false, byShards = false;
    std::vector<std::string> shardTexts;
    auto* planFlag = app.add_flag(
        "--plan", plan,
        "Region build, step 1: create OUTPUT.parts and print the shards of every level "
        "(with --json)");
    auto* shardOption =
        app.add_option(
               "--shard", shardTexts,
               "Region build, step 2: build shard LEVEL/X/Y into OUTPUT.parts; below the finest "
               "level, the shards of level + 1 beneath it and beside it must be built. Several "
               "(repeated, or LEVEL/X/Y,LEVEL/X/Y,…) are built one after another in this process")
            ->delimiter(',');
    auto* mergeFlag =
        app.add_flag("--merge", merge,
                     "Region build, step 3: once every shard is built, write the manifest and move "
                     "OUTPUT.parts to OUTPUT");
    auto* byShardsFlag = app.add_flag(
        "--by-shards", byShards,
        "Build one shard after another in this process (what a raster too wide for --memory "
        "gets anyway); planar: the files are the same as the whole build's; globe: the same "
        "patches and heights, with nested bounds above the finest level");
    planFlag->excludes(shardOption)->excludes(mergeFlag)->excludes(byShardsFlag);
    shardOption->excludes(mergeFlag)->excludes(byShardsFlag);
    mergeFlag->excludes(byShardsFlag);
    app.add_flag("--json", json, "Print a JSON summary on stdout");
    app.add_flag("-q,--quiet", quiet, "No progress bar");
    if (const auto status = terrain::tools::parseCommandLine(app, argc, argv)) return *status;

    auto fail = [](const std::string& message) {
        fmt::print(stderr, "terrain-build: {}\n", message);
        return 1;
    };
    const auto budget = parseBytes(memory);
    if (!budget) return fail("--memory '" + memory + "': expected a size such as 1GiB or 512MiB");
    options.memoryBudgetBytes = *budget;
    if (seaLevelOption->count() > 0 && !globe)
        return fail("--sea-level is for globe pyramids (--globe): a planar pyramid draws no sea");
    if (oversampleOption->count() > 0 && !globe)
        return fail(
            "--oversample-levels is for globe pyramids (--globe): a planar pyramid's finest "
            "level is the source's own grid");
    if (nativeFlag->count() > 0 && !globe)
        return fail(
            "--native-leaves is for globe pyramids (--globe): a planar pyramid's finest "
            "level is the source's own grid");
    if (!std::isfinite(options.globeSeaLevelM))
        return fail("--sea-level: expected a finite number of metres");
    options.parentPrediction = !independentPatches;
    const bool tasks = plan || merge || !shardTexts.empty();
    std::vector<io::ShardId> shards;
    for (const std::string& shardText : shardTexts) {
        io::ShardId id;
        char slash1 = 0, slash2 = 0, rest = 0;
        if (std::sscanf(shardText.c_str(), "%d%c%ld%c%ld%c", &id.level, &slash1, &id.x, &slash2,
                        &id.y, &rest) != 5 ||
            slash1 != '/' || slash2 != '/')
            return fail("--shard '" + shardText + "': expected LEVEL/X/Y, e.g. 5/3/2");
        shards.push_back(id);
    }
    // Several inputs are a mosaic on a plane; a globe composites them (finest valid sample
    // wins), so there each is a source of its own.
    std::vector<std::unique_ptr<io::DemReader>> sources;
    std::vector<io::DemReader*> sourcePointers;
    const bool composite = globe && inputs.size() > 1;
    // A globe takes projected sources resampled onto longitude/latitude grids.
    io::DemOpenOptions openOptions = demFlags.options();
    openOptions.geographicGrid = globe;
    for (std::size_t i = 0; i < (composite ? inputs.size() : 1); ++i) {
        auto opened =
            composite ? io::openDem({inputs[i]}, openOptions) : io::openDem(inputs, openOptions);
        if (!opened) return fail(opened.error().message);
        sourcePointers.push_back(opened.value().get());
        sources.push_back(std::move(opened).value());
    }
    // What the readers assumed, and relief no real terrain has: printed whatever --quiet
    // says (a wrong spacing or unit is the most common reason a pyramid looks broken).
    std::vector<std::string> warnings;
    for (const auto& source : sources) {
        for (const std::string& warning : source->info().warnings) warnings.push_back(warning);
        if (!shards.empty() || merge) continue;  // said once, when the build was planned
        auto slopes = io::sampleSlopes(*source);
        if (!slopes) return fail(slopes.error().message);
        if (auto absurd = io::absurdReliefWarning(source->info(), slopes.value()))
            warnings.push_back(*absurd);
    }
    for (const std::string& warning : warnings)
        fmt::print(stderr, "terrain-build: warning: {}\n", warning);
    const io::PyramidSurface surface =
        globe ? io::PyramidSurface::Globe : io::PyramidSurface::Plane;
    // A region build's steps take one source (buildPyramid checks --by-shards itself).
    if (tasks)
        if (Status shardable = io::shardable(surface, sourcePointers); !shardable)
            return fail(shardable.error().message);

    std::signal(SIGINT, onInterrupt);
    std::signal(SIGTERM, onInterrupt);
    options.cancel = &g_interrupted;
    std::optional<ProgressBar> bar;
    if (!quiet && isatty(fileno(stderr))) {
        bar.emplace();
        options.progress = [&](const io::PyramidBuildProgress& p) { bar->update(p); };
    }
    if (plan) {
        auto planned = io::planPyramidShards(surface, *sources.front(), output, options);
        if (!planned) return fail(planned.error().message);
        const io::ShardPlan& p = planned.value();
        // The planned shards of every level: on a plane each level's shard counts; on the
        // globe x0, y0, x1, y1, … of those that reach the source (a planet's finest level has
        // 1.6 million; a shard is built from its children 2x + 0|1, 2y + 0|1 the finer level
        // lists).
        nlohmann::json levels = nlohmann::json::array();
        std::size_t count = 0;
        for (int level = 0; level < p.layout.levelCount(); ++level) {
            const auto& levelShards = p.shards[static_cast<std::size_t>(level)];
            count += levelShards.size();
            if (!globe) {
                levels.push_back({{"level", level},
                                  {"shardsX", p.layout.shardsX(level)},
                                  {"shardsY", p.layout.shardsY(level)}});
                continue;
            }
            if (levelShards.empty()) continue;
            std::vector<std::int64_t> flat;
            flat.reserve(2 * levelShards.size());
            for (const io::ShardId& shard : levelShards) {
                flat.push_back(shard.x);
                flat.push_back(shard.y);
            }
            levels.push_back({{"level", level}, {"shards", std::move(flat)}});
        }
        nlohmann::json summary{{"tool", "terrain-build"},
                               {"tiling", globe ? "globe" : "planar"},
                               {"output", output},
                               {"staging", p.staging.string()},
                               {"finestLevel", p.layout.finestLevel()}};
        if (globe) summary["faceFinestLevel"] = p.faceFinestLevel;
        summary["levels"] = std::move(levels);
        summary["shardBytes"] = p.taskBytes;
        if (json)  // compact on the globe: a planet lists millions of shards
            std::puts(summary.dump(globe ? -1 : 2).c_str());
        else if (!quiet)
            fmt::print(stderr, "terrain-build: planned {} shards on {} levels in {}\n", count,
                       p.layout.levelCount(), p.staging.string());
        return 0;
    }
    if (!shards.empty()) {
        // One process for several shards saves each its start (libraries, the source's
        // header) and its share of a cluster's scheduling: tools/cluster batches them.
        nlohmann::json each = nlohmann::json::array();
        std::int64_t patches = 0, bytes = 0;
        double seconds = 0.0;
        for (std::size_t i = 0; i < shards.size(); ++i) {
            auto built =
                io::buildPyramidShard(surface, *sources.front(), output, shards[i], options);
            if (!built)
                return g_interrupted ? (fail(built.error().message), 130)
                                     : fail(built.error().message);
            const io::ShardBuildSummary& s = built.value();
            each.push_back({{"shard", shardTexts[i]},
                            {"patches", s.patches},
                            {"bytes", s.bytes},
                            {"seconds", s.seconds}});
            patches += s.patches;
            bytes += static_cast<std::int64_t>(s.bytes);
            seconds += s.seconds;
        }
        if (json) {
            nlohmann::json summary{{"tool", "terrain-build"},
                                   {"shards", each},
                                   {"patches", patches},
                                   {"bytes", bytes},
                                   {"seconds", seconds},
                                   {"peakRssBytes", peakResidentBytes()},
                                   {"memoryBudgetBytes", options.memoryBudgetBytes}};
            if (shards.size() == 1) summary["shard"] = shardTexts.front();
            std::puts(summary.dump(2).c_str());
        }
        return 0;
    }
    auto built =
        merge ? io::mergePyramidShards(surface, *sources.front(), output, options)
              : io::buildPyramid(surface, sourcePointers, output, options,
                                 byShards ? io::BuildWay::ByShards : io::BuildWay::Automatic);
    if (bar) bar->finish();
    if (!built)
        return g_interrupted ? (fail(built.error().message), 130) : fail(built.error().message);

    const io::PyramidBuildSummary& s = built.value();
    const io::DemInfo& dem = sources.front()->info();
    for (const std::string& warning : s.warnings) {
        fmt::print(stderr, "terrain-build: warning: {}\n", warning);
        warnings.push_back(warning);
    }
    if (json) {
        std::vector<std::string> inputFiles;  // every file read: folders and patterns expanded
        for (const auto& source : sources)
            inputFiles.insert(inputFiles.end(), source->info().inputs.begin(),
                              source->info().inputs.end());
        nlohmann::json levels = nlohmann::json::array();
        for (const auto& level : s.manifest.levels)
            levels.push_back({{"level", level.level},
                              {"patchesX", level.patchesX},
                              {"patchesY", level.patchesY},
                              {"presentPatches", level.presentPatches},
                              {"maxErrorM", level.maxError}});
        const auto manifestJson = nlohmann::json::parse(io::toJson(s.manifest));
        const nlohmann::json summary{
            {"tool", "terrain-build"},
            {"output", output},
            {"inputs", inputFiles},
            {"reader", dem.readerName},
            {"raster",
             {{"width", dem.width},
              {"height", dem.height},
              {"sampleType", dem.sampleType},
              {"band", dem.band},
              {"bands", dem.bandCount},
              {"subdataset",
               io::isGdalDatasetName(dem.path) ? nlohmann::json(dem.path) : nlohmann::json()},
              {"rowsFlipped", dem.rowsFlipped},
              {"columnsFlipped", dem.columnsFlipped},
              // As the manifest records it (source.resampled), or null.
              {"resampled", manifestJson["source"].value("resampled", nlohmann::json())}}},
            // As the manifest records it, or null for a lossless pyramid.
            {"quantization", manifestJson.value("quantization", nlohmann::json())},
            {"levels", s.manifest.levels.size()},
            {"tiling", s.manifest.globe ? "globe" : "planar"},
            {"faceFinestLevel", s.manifest.globe ? nlohmann::json(s.manifest.globe->faceFinestLevel)
                                                 : nlohmann::json()},
            {"levelDetails", levels},
            {"patches", s.patches},
            {"bytes", s.bytes},
            {"seconds", s.seconds},
            {"phaseSeconds",
             {{"read", s.phases.readSeconds},
              {"bounds", s.phases.boundsSeconds},
              {"write", s.phases.writeSeconds}}},
            {"peakRssBytes", peakResidentBytes()},
            {"memoryBudgetBytes", options.memoryBudgetBytes},
            {"compressionLevel", options.compressionLevel},
            {"parentPrediction", options.parentPrediction && !globe},
            {"rootErrorM", s.manifest.statistics.rootError},
            {"noDataSamples", s.manifest.noData.samples},
            {"noDataFill", s.manifest.noData.fill},
            {"filledSamples", terrain::tools::noDataSourcesJson<nlohmann::json>(s.manifest.noData)},
            {"seams", terrain::tools::seamsJson<nlohmann::json>(s.manifest)},
            {"warnings", warnings},
            {"gl", nullptr},
        };
        std::puts(summary.dump(2).c_str());
    } else if (!quiet) {
        fmt::print(stderr,
                   "terrain-build: {} → {}: {} levels, {} patches, {:.1f} MiB, {:.2f} s, peak RSS "
                   "{:.0f} MiB\n",
                   dem.path, output, s.manifest.levels.size(), s.patches,
                   double(s.bytes) / (1 << 20), s.seconds, double(peakResidentBytes()) / (1 << 20));
    }
    return 0;
}
