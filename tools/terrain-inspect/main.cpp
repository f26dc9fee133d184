// terrain-inspect: what a pyramid on disk holds (docs/pyramid-format.md), and with --verify
// whether every stored patch is intact and self-consistent.
#include "CommandLine.h"
#include "ImageryInspection.h"
#include "PyramidInspection.h"
#include "SourceBand.h"

#include "terrain/dem/OpenDem.h"
#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/pyramid/PyramidReader.h"
#include "terrain/pyramid/VirtualPlanetPyramid.h"

#include <fmt/format.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "DemOpenFlags.h"
#include "NoDataSourcesJson.h"
#include "SeamsJson.h"
#include "terrain/build/PyramidSourceCheck.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <unistd.h>

namespace {

namespace io = terrain::io;
namespace inspect = terrain::inspect;
namespace tools = terrain::tools;
using Json = nlohmann::ordered_json;

std::string bytesText(std::uintmax_t bytes) {
    const auto b = static_cast<double>(bytes);
    if (b >= 1e9) return fmt::format("{:.2f} GB", b * 1e-9);
    if (b >= 1e6) return fmt::format("{:.2f} MB", b * 1e-6);
    if (b >= 1e3) return fmt::format("{:.1f} kB", b * 1e-3);
    return fmt::format("{} B", bytes);
}

void printImagery(const std::vector<inspect::ImageryLayerSummary>& layers) {
    if (layers.empty()) return;
    fmt::print("\nimagery layers, bottom first:\n");
    for (const inspect::ImageryLayerSummary& l : layers)
        fmt::print("  {} ({}): levels {} to {}, opacity {}, {} tiles, {}{}\n", l.name, l.kind,
                   l.coarsestLevel, l.finestLevel, l.opacity, l.tiles, bytesText(l.bytes),
                   l.verified >= 0 ? fmt::format("; {} tiles read and checked", l.verified) : "");
}

/// A globe source's native grid (terrain-build --native-leaves): a planar pyramid of its own
/// samples inside the globe pyramid, inspected (and verified) as any planar pyramid is.
struct NativeGridSummary {
    std::string input, folder;
    std::int64_t width = 0, height = 0;
    std::int64_t patches = 0;
    std::uintmax_t bytes = 0;
    float finestMaxError = 0.0f;
};

std::vector<NativeGridSummary> inspectNativeGrids(const std::string& folder,
                                                  const io::PyramidManifest& manifest,
                                                  const inspect::InspectOptions& options,
                                                  std::vector<inspect::Problem>& problems) {
    std::vector<NativeGridSummary> grids;
    if (!manifest.globe) return grids;
    inspect::InspectOptions quiet = options;
    quiet.progress = nullptr;
    for (const io::ManifestGlobeSource& source : manifest.globe->sources) {
        if (source.native.empty()) continue;
        const std::string path = (std::filesystem::path(folder) / source.native).string();
        auto native = io::PyramidReader::open(path);
        if (!native) {
            problems.push_back({path, std::nullopt, native.error().message});
            continue;
        }
        inspect::Inspection inspected = inspect::inspectPyramid(native.value(), quiet);
        problems.insert(problems.end(), inspected.problems.begin(), inspected.problems.end());
        NativeGridSummary grid{source.input, source.native, native.value().layout().rasterWidth(),
                               native.value().layout().rasterHeight()};
        for (const inspect::LevelSummary& level : inspected.levels) {
            grid.patches += level.presentPatches;
            grid.bytes += level.bytes;
        }
        if (!inspected.levels.empty()) grid.finestMaxError = inspected.levels.back().maxError;
        grids.push_back(std::move(grid));
    }
    return grids;
}

Json imageryJson(const std::vector<inspect::ImageryLayerSummary>& layers) {
    Json out = Json::array();
    for (const inspect::ImageryLayerSummary& l : layers)
        out.push_back({{"name", l.name},
                       {"kind", l.kind},
                       {"coarsestLevel", l.coarsestLevel},
                       {"finestLevel", l.finestLevel},
                       {"opacity", l.opacity},
                       {"tiles", l.tiles},
                       {"bytes", l.bytes},
                       {"tilesVerified", l.verified >= 0 ? Json(l.verified) : Json(nullptr)}});
    return out;
}

void printText(const io::PyramidReader& reader, const inspect::Inspection& inspection, bool verify,
               const std::vector<inspect::ImageryLayerSummary>& imagery) {
    const io::PyramidManifest& m = reader.manifest();
    const io::Georeference& g = m.georeference;
    fmt::print("pyramid {}: {} version {}\n", reader.folder().string(),
               io::PyramidManifest::kFormatName, m.formatVersion);
    fmt::print(
        "raster: {} × {} samples; patches of {} samples (+1 apron), blocks of {} quads, "
        "shards of {} × {} patches; levels 0 to {}\n",
        m.layout.rasterWidth(), m.layout.rasterHeight(), m.layout.patchSamples(),
        m.layout.blockQuads(), m.layout.shardPatches(), m.layout.shardPatches(),
        m.layout.finestLevel());
    fmt::print("georeference: {}{}, origin ({}, {}), pixel {} × {}; metres = source × {} + {}{}\n",
               io::crsKindName(g.crsKind), g.epsg != 0 ? fmt::format(" EPSG:{}", g.epsg) : "",
               g.originX, g.originY, g.pixelSizeX, g.pixelSizeY, m.vertical.scale,
               m.vertical.offset, g.wkt.empty() ? "" : " (WKT given)");
    // Each source's no-data value and filled samples: a composite's sources declare their
    // own (a global grid's −9.99e33, SRTM's −32768). The pyramid's one value only where the
    // manifest records none per source (then the first source's).
    const auto valueText = [](const std::optional<double>& value) {
        return value ? fmt::format("{}", *value) : std::string("none");
    };
    const bool perSourceValues =
        std::any_of(m.noData.sources.begin(), m.noData.sources.end(),
                    [](const io::ManifestSourceNoData& s) { return s.sourceValueRecorded; });
    if (m.noData.present)
        fmt::print("no-data: {} samples filled ({}){}; shards carry the V mask\n", m.noData.samples,
                   m.noData.fill,
                   perSourceValues
                       ? ""
                       : fmt::format(
                             ", source value {}{}", valueText(m.noData.sourceValue),
                             m.source.inputs.size() > 1 && m.globe ? " (the first source's)" : ""));
    else
        fmt::print("no-data: none\n");
    for (const io::ManifestSourceNoData& source : m.noData.sources)
        fmt::print("  {}: no-data value {}, {} samples filled{}\n", source.input,
                   source.sourceValueRecorded ? valueText(source.sourceValue) : "not recorded",
                   source.samples,
                   source.samples > 0 && m.noData.fill == io::ManifestNoData::kDeltaSurfaceFill
                       ? fmt::format(", {} of them over the sources beneath", source.overBeneath)
                       : "");
    if (m.globe)
        for (const io::ManifestSeam& s : m.globe->seams)
            fmt::print(
                "  seam: {} blended into the sources beneath over {:.0f}–{:.0f} pixels "
                "({:.0f}–{:.0f} m{}); a step up to {:.0f} m adds a slope of {:.3f} ({:.1f}°), "
                "{} its 99th-percentile slope {:.3f} ({:.1f}°); at most {:.2f} of its "
                "99th-percentile slope over the band's width\n",
                s.input, s.bandPixels[0], s.bandPixels[1], s.bandMetres[0], s.bandMetres[1],
                s.cappedPixels > 0 ? fmt::format(", widest allowed along {} pixels", s.cappedPixels)
                                   : "",
                s.largestStepM, s.seamSlope, std::atan(s.seamSlope) * 180.0 / std::numbers::pi,
                tools::seamWithinSourceSlopes(s) ? "within" : "OVER", s.sourceSlopeP99,
                std::atan(s.sourceSlopeP99) * 180.0 / std::numbers::pi, s.bandScaleRatio);
    if (m.globe)
        fmt::print(
            "sea: at {} m in the sources' vertical datum ({}); at or below it is water\n",
            m.globe->seaLevelM,
            m.globe->seaLevelM == 0.0 ? "mean sea level" : "stated, terrain-build --sea-level");
    if (m.globe && m.globe->oversampleLevels > 0)
        fmt::print(
            "oversampled: {} face level{} below each source's spacing "
            "(terrain-build --oversample-levels)\n",
            m.globe->oversampleLevels, m.globe->oversampleLevels == 1 ? "" : "s");
    fmt::print("statistics: heights {} to {} m over {} valid samples; root Err(P) {} m\n",
               m.statistics.minHeight, m.statistics.maxHeight, m.statistics.validSamples,
               m.statistics.rootError);
    fmt::print("source: {} ({} reader, {}, band {} of {}{}{}); built by {} {} in {:.2f} s\n",
               fmt::join(m.source.inputs, ", "), m.source.reader, m.source.sampleType,
               m.source.band, m.source.bandCount, m.source.rowsFlipped ? ", rows flipped" : "",
               m.source.columnsFlipped ? ", columns flipped" : "", m.build.tool, m.build.version,
               m.build.seconds);
    if (const auto& q = m.quantization)
        fmt::print(
            "storage: lossy, every stored height within δ_l = {} m · 2^({} − level) of "
            "its exact value (Yusov 2011 §4; the finest level's largest difference {} m), "
            "and Err(P) covers it\n",
            q->maxErrorM, m.layout.finestLevel(), q->finestLargestErrorM);
    else
        fmt::print("storage: lossless\n");
    if (const auto& r = m.source.resampled)
        fmt::print(
            "resampled: a rotated or sheared grid of {} × {} ({} valid samples, geotransform {}) "
            "resampled {} onto this grid; its samples lie up to {} m from the finest level, and "
            "every Err(P) covers them\n",
            r->width, r->height, r->validSamples, fmt::join(r->geoTransform, ", "), r->method,
            r->finestDistanceM);
    fmt::print("\n{:>5} {:>13} {:>10} {:>9} {:>11}   {}\n", "level", "patches", "present", "shards",
               "on disk", "Err(P) min / median / max, m");
    std::int64_t patches = 0, present = 0, shards = 0;
    std::uintmax_t bytes = 0;
    for (const inspect::LevelSummary& l : inspection.levels) {
        fmt::print("{:>5} {:>13} {:>10} {:>9} {:>11}   {} / {} / {}{}\n", l.level,
                   fmt::format("{} × {}", l.patchesX, l.patchesY), l.presentPatches, l.shards,
                   bytesText(l.bytes), l.minError, l.medianError, l.maxError,
                   l.missingShards > 0
                       ? fmt::format("  ({} shards missing or unreadable)", l.missingShards)
                       : "");
        patches += l.patchesX * l.patchesY;
        present += l.presentPatches;
        shards += l.shards;
        bytes += l.bytes;
    }
    fmt::print("{:>5} {:>13} {:>10} {:>9} {:>11}\n", "all", patches, present, shards,
               bytesText(bytes));
    if (verify)
        fmt::print("\nverify: {} patches read and checked in {:.2f} s ({:.0f} patches/s)\n",
                   inspection.patchesVerified, inspection.verifySeconds,
                   inspection.verifySeconds > 0.0
                       ? static_cast<double>(inspection.patchesVerified) / inspection.verifySeconds
                       : 0.0);
    printImagery(imagery);
    for (const inspect::Problem& p : inspection.problems) fmt::print("problem: {}\n", p.message);
    fmt::print("{}\n", inspection.problems.empty()
                           ? "no problems found"
                           : fmt::format("{} problems found", inspection.problems.size()));
}

Json summaryJson(const io::PyramidReader& reader, const inspect::Inspection& inspection,
                 bool verify) {
    Json j;
    j["pyramid"] = reader.folder().string();
    j["manifest"] = Json::parse(io::toJson(reader.manifest()));
    Json levels = Json::array();
    for (const inspect::LevelSummary& l : inspection.levels) {
        levels.push_back(
            {{"level", l.level},
             {"patchesX", l.patchesX},
             {"patchesY", l.patchesY},
             {"presentPatches", l.presentPatches},
             {"shards", l.shards},
             {"missingShards", l.missingShards},
             {"bytes", l.bytes},
             {"error", {{"min", l.minError}, {"median", l.medianError}, {"max", l.maxError}}}});
    }
    j["levels"] = std::move(levels);
    j["noDataSources"] = tools::noDataSourcesJson<Json>(reader.manifest().noData);
    j["seams"] = tools::seamsJson<Json>(reader.manifest());
    if (reader.manifest().globe) {
        j["seaLevelM"] = reader.manifest().globe->seaLevelM;
        j["oversampleLevels"] = reader.manifest().globe->oversampleLevels;
    }
    if (verify) {
        j["verify"] = {{"patchesChecked", inspection.patchesVerified},
                       {"seconds", inspection.verifySeconds},
                       {"patchesPerSecond", inspection.verifySeconds > 0.0
                                                ? static_cast<double>(inspection.patchesVerified) /
                                                      inspection.verifySeconds
                                                : 0.0}};
    } else {
        j["verify"] = nullptr;
    }
    Json problems = Json::array();
    for (const inspect::Problem& p : inspection.problems) {
        Json problem{{"file", p.file}, {"patch", nullptr}, {"message", p.message}};
        if (p.patch)
            problem["patch"] = {{"level", p.patch->level}, {"x", p.patch->x}, {"y", p.patch->y}};
        problems.push_back(std::move(problem));
    }
    j["problems"] = std::move(problems);
    j["ok"] = inspection.problems.empty();
    return j;
}

}  // namespace

// The virtual planet stores nothing: what it would hold, from its manifest, with each face
// level's Err(P) (every patch of a level has the same bound). Its bounds are checked by
// VirtualPlanetPyramidTest, not by reading patches back.
int describeVirtualPlanet(const io::PyramidManifest& m, const std::string& name, bool json,
                          bool verify) {
    if (verify) {
        std::fprintf(stderr,
                     "terrain-inspect: %s: the virtual planet stores nothing to verify: its "
                     "patches are generated when read (terrain-stress checks them streaming)\n",
                     name.c_str());
        return 1;
    }
    const int offset = io::ManifestGlobe::kLevelOffset;
    if (json) {
        Json levels = Json::array();
        for (const io::ManifestLevel& level : m.levels) {
            if (level.level < offset) continue;
            levels.push_back({{"faceLevel", level.level - offset},
                              {"patches", level.presentPatches},
                              {"errorM", level.maxError}});
        }
        const Json j = {{"tool", "terrain-inspect"},
                        {"pyramid", name},
                        {"virtual", true},
                        {"tiling", "globe"},
                        {"faceFinestLevel", m.globe->faceFinestLevel},
                        {"heightBoundM", m.statistics.maxHeight},
                        {"levels", levels}};
        std::printf("%s\n", j.dump(2).c_str());
        return 0;
    }
    fmt::print(
        "pyramid {}: the built-in planet, virtual: face levels 0 to {} generated when "
        "read, nothing on disk; heights within ±{:.0f} m\n\n",
        name, m.globe->faceFinestLevel, m.statistics.maxHeight);
    fmt::print("face level   patches   mean spacing   Err(P), m\n");
    for (const io::ManifestLevel& level : m.levels) {
        if (level.level < offset) continue;
        const int face = level.level - offset;
        fmt::print("{:>10} {:>9} {:>12.1f} m {:>11.2f}\n", face, level.presentPatches,
                   20037508.3 / 2.0 / std::ldexp(double(m.layout.patchQuads()), face),
                   level.maxError);
    }
    return 0;
}

int main(int argc, char** argv) {
    CLI::App app{
        "terrain-inspect: describe a terrain pyramid (docs/pyramid-format.md): format version, "
        "raster, georeference, no-data, and per level the patches, present patches, shards, "
        "bytes on disk and Err(P) statistics; checks that error bounds nest. With --verify "
        "every present patch is read back and checked: checksum, finite heights, min/max, "
        "block errors λ(d) recomputed, Err(P) ≥ Err_Appr(P) ≥ 0, no-data count. Exit status: "
        "0 no problem, 1 problems found or not a pyramid."};
    std::string folder;
    bool json = false;
    bool verify = false;
    app.add_option("PYRAMID", folder, "Pyramid folder (holding manifest.json)")->required();
    app.add_flag("--verify", verify, "Read and check every present patch of every level");
    app.add_flag("--json", json, "Print a JSON summary on stdout instead of text");
    std::vector<std::string> sources;
    tools::DemOpenFlags demFlags;
    app.add_option("--source", sources,
                   "With --verify: the DEM the pyramid was built from (several files: a mosaic); "
                   "every valid sample is checked against Err(P) of the patch covering it at "
                   "every level, for both diagonals of its cell")
        ->needs("--verify");
    demFlags.addTo(app);
    if (const auto status = terrain::tools::parseCommandLine(app, argc, argv)) return *status;

    auto reader = io::PyramidReader::open(folder);
    if (!reader) {
        std::fprintf(stderr, "terrain-inspect: %s\n", reader.error().message.c_str());
        return 1;
    }
    if (io::isVirtualPlanetName(folder))
        return describeVirtualPlanet(reader.value().manifest(), folder, json, verify);
    // The source is read as it was built: the band the manifest records (refused before the
    // patches are read when -b names another).
    io::DemOpenOptions openOptions = demFlags.options();
    if (!sources.empty()) {
        auto band = inspect::sourceBand(reader.value().manifest().source, openOptions.band, folder);
        if (!band) {
            std::fprintf(stderr, "terrain-inspect: %s\n", band.error().message.c_str());
            return 1;
        }
        openOptions.band = band.value();
    }
    inspect::InspectOptions options;
    options.verify = verify;
    const bool showProgress = isatty(STDERR_FILENO) == 1;
    int shownPercent = -1;
    const auto start = std::chrono::steady_clock::now();
    if (showProgress) {
        options.progress = [&](double fraction) {
            const int percent = static_cast<int>(fraction * 100.0);
            const double seconds =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            if (percent == shownPercent || seconds < 1.0) return;
            shownPercent = percent;
            std::fprintf(stderr, "\rterrain-inspect: %s %3d%%", folder.c_str(), percent);
            std::fflush(stderr);
        };
    }
    inspect::Inspection inspection = inspect::inspectPyramid(reader.value(), options);
    if (shownPercent >= 0) std::fprintf(stderr, "\n");
    const std::vector<inspect::ImageryLayerSummary> imagery =
        inspect::inspectImagery(folder, reader.value().manifest(), verify, inspection.problems);
    const std::vector<NativeGridSummary> nativeGrids =
        inspectNativeGrids(folder, reader.value().manifest(), options, inspection.problems);
    std::optional<io::SourceCheckReport> sourceCheck;
    if (!sources.empty()) {
        const bool globe = reader.value().manifest().globe.has_value();
        // A globe's sources were composited, each one on its own; a plane's form a mosaic.
        std::vector<std::unique_ptr<io::DemReader>> opened;
        std::vector<io::DemReader*> openedPointers;
        // Opened as the build opened them: projected ones onto longitude/latitude grids.
        openOptions.geographicGrid = globe;
        for (std::size_t i = 0; i < (globe ? sources.size() : 1); ++i) {
            auto one =
                globe ? io::openDem({sources[i]}, openOptions) : io::openDem(sources, openOptions);
            if (!one) {
                std::fprintf(stderr, "terrain-inspect: %s\n", one.error().message.c_str());
                return 1;
            }
            openedPointers.push_back(one.value().get());
            opened.push_back(std::move(one).value());
        }
        auto checked = io::checkErrorBoundsAgainstSources(folder, openedPointers);
        if (!checked) {
            inspection.problems.push_back(
                inspect::Problem{sources.front(), std::nullopt, checked.error().message});
        } else {
            sourceCheck = std::move(checked).value();
            for (const io::ErrorBoundViolation& v : sourceCheck->violations)
                inspection.problems.push_back(inspect::patchProblem(
                    reader.value().shardFile(v.patch).string(), v.patch,
                    v.stored ? fmt::format("DEM sample ({}, {}) is stored {:.6f} m from the "
                                           "source's value, beyond δ = {:.6f} m",
                                           v.x, v.y, v.distanceM, v.boundM)
                             : fmt::format("DEM sample ({}, {}) is {:.6f} m from the surface, "
                                           "beyond Err(P) = {:.6f} m",
                                           v.x, v.y, v.distanceM, v.boundM)));
            if (sourceCheck->filledBeyondRimCount > 0)
                inspection.problems.push_back(inspect::Problem{
                    sources.front(), std::nullopt,
                    fmt::format("{} filled samples are drawn further from the source beneath "
                                "than the largest difference at a void's rim ({:.3f} m) and "
                                "their patch's Err(P)",
                                sourceCheck->filledBeyondRimCount,
                                sourceCheck->largestRimDifferenceM)});
        }
    }
    if (json) {
        Json summary = summaryJson(reader.value(), inspection, verify);
        summary["sourceCheck"] = nullptr;
        if (sourceCheck)
            summary["sourceCheck"] = {
                {"source", sources},
                {"samplesChecked", sourceCheck->samplesChecked},
                {"violations", sourceCheck->violationCount},
                {"tightestRatioPerLevel", sourceCheck->tightestRatio},
                {"storedSamplesChecked", sourceCheck->storedSamplesChecked},
                {"storedViolations", sourceCheck->storedViolationCount},
                {"largestStoredDifferencePerLevelM", sourceCheck->largestStoredDifference},
                {"filledSamplesChecked", sourceCheck->filledSamplesChecked},
                {"largestFilledDeviationM", sourceCheck->largestFilledDeviationM},
                {"largestRimDifferenceM", sourceCheck->largestRimDifferenceM},
                {"filledBeyondRim", sourceCheck->filledBeyondRimCount}};
        summary["imagery"] = imageryJson(imagery);
        Json natives = Json::array();
        for (const NativeGridSummary& grid : nativeGrids)
            natives.push_back({{"input", grid.input},
                               {"folder", grid.folder},
                               {"width", grid.width},
                               {"height", grid.height},
                               {"patches", grid.patches},
                               {"bytes", grid.bytes},
                               {"finestMaxError", grid.finestMaxError}});
        summary["nativeGrids"] = std::move(natives);
        summary["ok"] = inspection.problems.empty();
        std::printf("%s\n", summary.dump(2).c_str());
    } else {
        printText(reader.value(), inspection, verify, imagery);
        for (const NativeGridSummary& grid : nativeGrids)
            fmt::print(
                "native grid: {} at its own samples in {}: {} × {} samples, {} patches, {}, "
                "finest Err(P) {} m{}\n",
                grid.input, grid.folder, grid.width, grid.height, grid.patches,
                bytesText(grid.bytes), grid.finestMaxError, verify ? ", every patch verified" : "");
        if (sourceCheck) {
            fmt::print(
                "source check: {} (sample, level) pairs, {} beyond Err(P); largest "
                "distance / Err(P) per level:",
                sourceCheck->samplesChecked, sourceCheck->violationCount);
            for (double ratio : sourceCheck->tightestRatio) fmt::print(" {:.3f}", ratio);
            fmt::print("\n");
            if (sourceCheck->storedSamplesChecked > 0) {
                fmt::print(
                    "stored samples: {} (sample, level) pairs on the levels' grids, {} beyond "
                    "δ; largest |stored − source| per level, m:",
                    sourceCheck->storedSamplesChecked, sourceCheck->storedViolationCount);
                for (double d : sourceCheck->largestStoredDifference) fmt::print(" {:.4g}", d);
                fmt::print("\n");
            }
            if (sourceCheck->filledSamplesChecked > 0)
                fmt::print(
                    "filled samples: {} over a source beneath, drawn at most {:.3f} m from it "
                    "(the largest difference at a void's rim {:.3f} m), {} beyond that and "
                    "Err(P)\n",
                    sourceCheck->filledSamplesChecked, sourceCheck->largestFilledDeviationM,
                    sourceCheck->largestRimDifferenceM, sourceCheck->filledBeyondRimCount);
        }
    }
    if (!inspection.problems.empty()) {
        std::fprintf(stderr, "terrain-inspect: %s: %zu problems found\n", folder.c_str(),
                     inspection.problems.size());
        return 1;
    }
    return 0;
}
