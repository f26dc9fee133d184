// terrain-generate: writes any window of the procedural DEM (io/ProceduralTerrain.h) as a
// GeoTIFF, 16-bit PNG, OpenEXR file or SRTM .hgt tile, streaming band by band so any size
// fits in memory; or the whole DEM as a folder of SRTM tiles (--srtm-tiles).
#include "CommandLine.h"

#include "terrain/base/AtomicFile.h"
#include "terrain/dem/HeightImageWriter.h"
#include "terrain/source/ProceduralTerrain.h"

#include <fmt/format.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <unistd.h>

namespace {

using terrain::io::HeightImageFormat;
using terrain::io::ProceduralTerrain;

constexpr std::int64_t kProgressMinSamples = std::int64_t{4} << 20U;   // ~2,049²
constexpr std::int64_t kPngInMemorySamples = std::int64_t{64} << 20U;  // 256 MiB of floats

nlohmann::ordered_json featuresJson(const ProceduralTerrain& terrain) {
    nlohmann::ordered_json features;
    if (terrain.hasCliff()) {
        features["cliff"] = {{"height_m", terrain.cliffHeightM()},
                             {"column_at_first_row", terrain.cliffColumn(0)},
                             {"column_at_last_row", terrain.cliffColumn(terrain.height() - 1)},
                             {"note", "in row y, sample (c, y) stands height_m above (c + 1, y)"}};
    } else {
        features["cliff"] = nullptr;
    }
    if (const auto& lake = terrain.lake()) {
        features["lake"] = {{"centre_x", lake->centreX},
                            {"centre_y", lake->centreY},
                            {"radius_samples", lake->radiusSamples},
                            {"level_m", lake->levelM}};
    } else {
        features["lake"] = nullptr;
    }
    features["plateaus"] = nlohmann::ordered_json::array();
    for (const auto& p : terrain.plateaus()) {
        features["plateaus"].push_back({{"centre_x", p.centreX},
                                        {"centre_y", p.centreY},
                                        {"radius_samples", p.radiusSamples},
                                        {"top_m", p.topHeightM}});
    }
    features["spikes"] = nlohmann::ordered_json::array();
    for (const auto& s : terrain.spikes()) {
        features["spikes"].push_back({{"x", s.x},
                                      {"y", s.y},
                                      {"height_m", s.heightM},
                                      {"above_neighbours_m", s.heightAboveNeighboursM}});
    }
    return features;
}

// The DEM as columns × rows SRTM 3" tiles in `folder`, each a 1201² window whose edges its
// neighbours share; the tile `row` rows south of the northern ones covers latitudes
// south + rows − 1 − row … + 1.
int writeSrtmTiles(const ProceduralTerrain& terrain, const std::filesystem::path& folder,
                   int columns, int rows, int south, int west, unsigned threads, bool json) {
    std::error_code ec;
    std::filesystem::create_directories(folder, ec);
    if (ec) {
        std::fprintf(stderr, "terrain-generate: %s: cannot create the folder: %s\n", folder.c_str(),
                     ec.message().c_str());
        return 1;
    }
    nlohmann::ordered_json tiles = nlohmann::ordered_json::array();
    for (int row = 0; row < rows; ++row) {
        for (int column = 0; column < columns; ++column) {
            const int latitude = south + rows - 1 - row, longitude = west + column;
            const std::string name =
                fmt::format("{}{:02}{}{:03}.hgt", latitude < 0 ? 'S' : 'N', std::abs(latitude),
                            longitude < 0 ? 'W' : 'E', std::abs(longitude));
            const std::int64_t x0 = std::int64_t{column} * 1200, y0 = std::int64_t{row} * 1200;
            auto written = terrain::io::writeHeightImage(
                folder / name, 1201, 1201,
                [&](std::int64_t firstRow, std::int64_t rowCount, std::span<float> out) {
                    terrain.fillWindow(x0, y0 + firstRow, 1201, rowCount, out, threads);
                });
            if (!written) {
                std::fprintf(stderr, "terrain-generate: %s\n", written.error().message.c_str());
                return 1;
            }
            tiles.push_back(name);
        }
    }
    if (json) {
        nlohmann::ordered_json j;
        j["output"] = folder.string();
        j["format"] = "hgt";
        j["tiles"] = tiles;
        j["size"] = {{"width", terrain.width()}, {"height", terrain.height()}};
        j["gl"] = nullptr;
        std::printf("%s\n", j.dump(2).c_str());
    } else {
        fmt::print("wrote {} SRTM tiles of the {} × {} DEM into {}\n", tiles.size(),
                   terrain.width(), terrain.height(), folder.string());
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{
        "terrain-generate: write a window of the procedural test DEM (ridged mountains, a "
        "vertical fault cliff, single-sample spikes, a flat lake, mesas) as a float32 GeoTIFF "
        "(.tif), 16-bit PNG (.png: metres = offset + grey × scale) or float32 OpenEXR (.exr, "
        "channel Y). Rows run north to south; the DEM spans [0, W·spacing] × [0, H·spacing] "
        "in an unnamed projected CRS (or --epsg)."};
    terrain::io::ProceduralTerrainParameters params;
    std::string output;
    std::int64_t size = 0;
    std::vector<std::int64_t> window;
    double pngScale = 0.1;
    std::optional<double> pngOffset;
    int epsg = 0;
    std::string compression = "deflate";
    std::string bigTiff = "auto";
    unsigned threads = 0;
    bool json = false;

    app.add_option("-o,--output", output,
                   "Output file: .tif/.tiff, .png, .exr or .hgt (an SRTM tile, 1201² or 3601²); "
                   "with --srtm-tiles, a folder")
        ->required();
    std::vector<int> srtmTiles;
    int south = 46, west = -122;
    auto* tilesOption =
        app.add_option("--srtm-tiles", srtmTiles,
                       "Write the DEM as COLUMNS,ROWS SRTM 3\" .hgt tiles of 1201² samples "
                       "(neighbours share their edge samples, as SRTM's do) into the output "
                       "folder, the south-west one named by --south and --west; the DEM is "
                       "sized to fit")
            ->expected(2)
            ->delimiter(',');
    app.add_option("--south", south, "--srtm-tiles: latitude of the southern tiles' south edge")
        ->capture_default_str();
    app.add_option("--west", west, "--srtm-tiles: longitude of the western tiles' west edge")
        ->capture_default_str();
    auto* sizeOption = app.add_option("--size", size, "Square DEM of N × N samples (default 1025)");
    auto* widthOption = app.add_option("--width", params.widthSamples, "DEM width in samples");
    auto* heightOption = app.add_option("--height", params.heightSamples, "DEM height in samples");
    sizeOption->excludes(widthOption)->excludes(heightOption);
    tilesOption->excludes(sizeOption)->excludes(widthOption)->excludes(heightOption);
    app.add_option("--window", window,
                   "Part of the DEM to write: X,Y,W,H (north-west sample and size); default all")
        ->expected(4)
        ->delimiter(',');
    app.add_option("--seed", params.seed, "Seed (any 64-bit number)")->capture_default_str();
    app.add_option("--spacing", params.sampleSpacingM, "Sample spacing in metres")
        ->capture_default_str();
    app.add_option("--png-scale", pngScale, "PNG metres per grey level")->capture_default_str();
    app.add_option("--png-offset", pngOffset,
                   "PNG height of grey 0 in metres (default: floor of the window's minimum)");
    app.add_option("--epsg", epsg, "GeoTIFF projected CRS EPSG code (default: unnamed, metres)");
    app.add_option("--compression", compression, "GeoTIFF compression")
        ->check(CLI::IsMember({"none", "deflate"}))
        ->capture_default_str();
    app.add_option("--bigtiff", bigTiff, "GeoTIFF BigTIFF: auto (from 4 GiB), always, never")
        ->check(CLI::IsMember({"auto", "always", "never"}))
        ->capture_default_str();
    app.add_option("--threads", threads, "Generation threads (0: one per hardware thread)")
        ->capture_default_str();
    app.add_option("--octaves", params.octaves, "Ridged octaves (0: down to 2 samples)")
        ->capture_default_str();
    app.add_option("--hill-height", params.hillHeightM, "Hill relief in metres")
        ->capture_default_str();
    app.add_option("--mountain-height", params.mountainHeightM, "Mountain relief in metres")
        ->capture_default_str();
    app.add_option("--cliff-height", params.cliffHeightM, "Fault step in metres (0: none)")
        ->capture_default_str();
    app.add_option("--plateau-count", params.plateauCount, "Mesas")->capture_default_str();
    app.add_option("--plateau-height", params.plateauHeightM, "Mesa height in metres")
        ->capture_default_str();
    app.add_option("--lake-radius", params.lakeRadius, "Lake radius, fraction of the DEM (0: none)")
        ->capture_default_str();
    app.add_option("--spike-count", params.spikeCount, "Single-sample spikes")
        ->capture_default_str();
    app.add_option("--spike-height", params.spikeHeightM, "Spike height above its neighbours, m")
        ->capture_default_str();
    app.add_flag("--json", json, "Print a JSON summary on stdout");
    if (const auto status = terrain::tools::parseCommandLine(app, argc, argv)) return *status;

    const auto fail = [](const std::string& message) {
        std::fprintf(stderr, "terrain-generate: %s\n", message.c_str());
        return 1;
    };
    if (size != 0) params.widthSamples = params.heightSamples = size;
    if (!srtmTiles.empty()) {
        if (srtmTiles[0] < 1 || srtmTiles[1] < 1 || srtmTiles[0] > 360 || srtmTiles[1] > 180 ||
            south < -90 || south + srtmTiles[1] > 90 || west < -180 || west + srtmTiles[0] > 180)
            return fail(
                fmt::format("--srtm-tiles {},{} from {}° N, {}° E: the tiles must lie on "
                            "the globe",
                            srtmTiles[0], srtmTiles[1], south, west));
        params.widthSamples = std::int64_t{srtmTiles[0]} * 1200 + 1;
        params.heightSamples = std::int64_t{srtmTiles[1]} * 1200 + 1;
        auto tiled = ProceduralTerrain::create(params);
        if (!tiled) return fail(tiled.error().message);
        return writeSrtmTiles(
            tiled.value(), output, srtmTiles[0], srtmTiles[1], south, west,
            threads == 0 ? std::max(1U, std::thread::hardware_concurrency()) : threads, json);
    }
    // Check the output name before the (possibly long) generation.
    const auto format = terrain::io::heightImageFormatFor(output);
    if (!format) return fail(format.error().message);
    auto created = ProceduralTerrain::create(params);
    if (!created) return fail(created.error().message);
    const ProceduralTerrain& terrain = created.value();

    std::int64_t wx = 0, wy = 0, ww = terrain.width(), wh = terrain.height();
    if (!window.empty()) {
        wx = window[0];
        wy = window[1];
        ww = window[2];
        wh = window[3];
        if (ww < 1 || wh < 1 || wx < 0 || wy < 0 || wx > terrain.width() - ww ||
            wy > terrain.height() - wh)
            return fail(fmt::format("window {},{},{},{} does not lie inside the {} × {} DEM", wx,
                                    wy, ww, wh, terrain.width(), terrain.height()));
    }
    if (threads == 0) threads = std::max(1U, std::thread::hardware_concurrency());
    const double samples = static_cast<double>(ww) * static_cast<double>(wh);
    // Fail on an unwritable folder now, not after a long generation (the probe's temporary
    // file is removed again at once).
    if (auto probe = terrain::AtomicFile::create(output); !probe)
        return fail(probe.error().message);

    terrain::io::HeightImageOptions options;
    if (format.value() == HeightImageFormat::GeoTiff)
        options.georeference = terrain.windowGeoreference(wx, wy, epsg);
    options.tiffCompression = compression == "none" ? terrain::io::TiffCompression::None
                                                    : terrain::io::TiffCompression::Deflate;
    options.bigTiff = bigTiff == "always"  ? terrain::io::BigTiffMode::Always
                      : bigTiff == "never" ? terrain::io::BigTiffMode::Never
                                           : terrain::io::BigTiffMode::Automatic;
    options.pngScaleM = pngScale;
    options.pngOffsetM = pngOffset;
    const bool showProgress =
        isatty(STDERR_FILENO) == 1 && samples >= static_cast<double>(kProgressMinSamples);
    int shownPercent = -1;
    if (showProgress) {
        options.progress = [&](double fraction) {
            const int percent = static_cast<int>(fraction * 100.0);
            if (percent == shownPercent) return;
            shownPercent = percent;
            std::fprintf(stderr, "\rterrain-generate: %s %3d%%", output.c_str(), percent);
            std::fflush(stderr);
        };
    }

    using Clock = std::chrono::steady_clock;
    double generateSeconds = 0.0;
    const auto source = [&](std::int64_t firstRow, std::int64_t rowCount, std::span<float> out) {
        const auto start = Clock::now();
        terrain.fillWindow(wx, wy + firstRow, ww, rowCount, out, threads);
        generateSeconds += std::chrono::duration<double>(Clock::now() - start).count();
    };
    const auto start = Clock::now();
    std::optional<terrain::Result<terrain::io::HeightImageSummary>> maybeWritten;
    if (format.value() == HeightImageFormat::Png16 && !pngOffset &&
        samples <= static_cast<double>(kPngInMemorySamples)) {
        // The PNG writer reads its source twice to find the offset; generating twice
        // costs more than holding a window this small.
        std::vector<float> heights(static_cast<std::size_t>(ww * wh));
        source(0, wh, heights);
        maybeWritten =
            terrain::io::writeHeightImage(output, ww, wh, std::span<const float>(heights), options);
    } else {
        maybeWritten = terrain::io::writeHeightImage(output, ww, wh, source, options);
    }
    auto& written = *maybeWritten;
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    if (showProgress) std::fprintf(stderr, "\n");
    if (!written) return fail(written.error().message);
    const terrain::io::HeightImageSummary& summary = written.value();

    if (json) {
        nlohmann::ordered_json j;
        j["output"] = output;
        j["format"] = std::string(terrain::io::formatName(summary.format));
        j["window"] = {{"x", wx}, {"y", wy}, {"width", ww}, {"height", wh}};
        j["size"] = {{"width", terrain.width()}, {"height", terrain.height()}};
        j["seed"] = params.seed;
        j["spacing_m"] = params.sampleSpacingM;
        j["octaves"] = terrain.octaves();
        j["threads"] = threads;
        j["min_height_m"] = summary.minHeightM;
        j["max_height_m"] = summary.maxHeightM;
        if (summary.png) {
            j["png_scale_m"] = summary.png->scaleM;
            j["png_offset_m"] = summary.png->offsetM;
            j["png_clamped_samples"] = summary.png->clampedSamples;
        } else {
            j["png_scale_m"] = nullptr;
            j["png_offset_m"] = nullptr;
        }
        if (options.georeference) {
            const auto& g = *options.georeference;
            j["georeference"] = {{"origin_x", g.originX},
                                 {"origin_y", g.originY},
                                 {"pixel_size_x", g.pixelSizeX},
                                 {"pixel_size_y", g.pixelSizeY},
                                 {"epsg", g.epsg == 0 ? nlohmann::ordered_json(nullptr)
                                                      : nlohmann::ordered_json(g.epsg)}};
            j["bigtiff"] = summary.bigTiff;
        }
        j["seconds"] = seconds;
        j["generate_seconds"] = generateSeconds;
        j["samples_per_second"] = samples / seconds;
        j["features"] = featuresJson(terrain);
        j["gl"] = nullptr;  // this tool does not use OpenGL
        std::printf("%s\n", j.dump(2).c_str());
    } else {
        fmt::print(
            "wrote {}: {}, {} × {} samples of the {} × {} DEM (seed {}), heights {:.3f} to "
            "{:.3f} m, {:.2f} s ({:.1f} M samples/s)\n",
            output, terrain::io::formatName(summary.format), ww, wh, terrain.width(),
            terrain.height(), params.seed, summary.minHeightM, summary.maxHeightM, seconds,
            samples / seconds * 1e-6);
        if (summary.png)
            fmt::print("PNG heights: metres = {} + grey × {} ({} samples clamped)\n",
                       summary.png->offsetM, summary.png->scaleM, summary.png->clampedSamples);
    }
    return 0;
}
