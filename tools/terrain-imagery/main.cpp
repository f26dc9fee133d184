// terrain-imagery: builds an imagery layer of a pyramid from an image (docs/imagery.md) and
// records it in the pyramid's manifest: the tiles into PYRAMID/imagery/<name>, then the
// manifest rewritten atomically with the layer appended (or replaced).
#include "CommandLine.h"

#include "terrain/build/ImageryLayerBuilder.h"
#include "terrain/dem/OpenImageryImage.h"
#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/pyramid/VirtualPlanetPyramid.h"

#include <fmt/format.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <string>

namespace {

namespace io = terrain::io;
namespace fs = std::filesystem;

int fail(const std::string& message) {
    std::fprintf(stderr, "terrain-imagery: %s\n", message.c_str());
    return 1;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{
        "terrain-imagery: drape an image over a pyramid (docs/imagery.md). Builds an imagery "
        "layer on the pyramid's own tiling (WebP tiles in PYRAMID/imagery/<name>) from any "
        "8-bit raster GDAL opens (RGB, RGBA, grey, palette; no-data and alpha kept), in any "
        "CRS PROJ transforms, then adds it to the pyramid's manifest above the layers already "
        "there. Exit status 0, or 1 with a message and nothing written."};
    std::string pyramid, imagePath, name;
    double opacity = 1.0;
    int quality = 85;
    bool lossless = false, demExtent = false, replace = false, json = false;
    int threads = 0;
    double finestTexelPixels = terrain::io::ImageryBuildOptions{}.finestTexelPixels;
    app.add_option("PYRAMID", pyramid, "Pyramid folder (holding manifest.json)")->required();
    app.add_option("IMAGE", imagePath, "The image (a file or a GDAL dataset name)")->required();
    app.add_option("--name", name, "The layer's name (default: the image's file stem)");
    app.add_option("--opacity", opacity, "The layer's opacity, 0 to 1")
        ->check(CLI::Range(0.0, 1.0))
        ->capture_default_str();
    auto* qualityOption = app.add_option("--quality", quality, "Lossy WebP quality, 0 to 100")
                              ->check(CLI::Range(0, 100))
                              ->capture_default_str();
    app.add_flag("--lossless", lossless, "Store the tiles as lossless WebP")
        ->excludes(qualityOption);
    app.add_flag("--dem-extent", demExtent,
                 "Lay the image over the DEM's extent (its outer edges on the DEM's first and "
                 "last samples) whatever its georeference: for a picture without one (planar "
                 "pyramids)");
    app.add_option("--finest-texel-pixels", finestTexelPixels,
                   "The finest level is the first whose texel is at most this many of the "
                   "image's pixels (1: never coarser than the image; the default keeps an "
                   "image at a power-of-two multiple of the patch grid, whose texel is 256/248 "
                   "of its pixel, at its own resolution rather than a level of 4x the texels)")
        ->check(CLI::Range(0.5, 2.0))
        ->capture_default_str();
    app.add_flag("--replace", replace, "Replace a layer of the same name");
    app.add_option("--threads", threads, "Threads building tiles (default: up to 8)");
    app.add_flag("--json", json, "Print a JSON summary on stdout");
    if (const auto status = terrain::tools::parseCommandLine(app, argc, argv)) return *status;

    if (name.empty()) name = fs::path(imagePath).stem().string();
    if (name.empty() || name == "." || name == ".." ||
        name.find_first_of("/\\") != std::string::npos)
        return fail(fmt::format("--name \"{}\": a layer's name must be a plain folder name", name));
    if (io::isVirtualPlanetName(pyramid))
        return fail(fmt::format("{}: the virtual planet stores no imagery layers", pyramid));
    auto read = io::readManifest(pyramid);
    if (!read) return fail(read.error().message);
    io::PyramidManifest manifest = std::move(read).value();
    std::size_t existing = manifest.imagery.size();
    for (std::size_t i = 0; i < manifest.imagery.size(); ++i)
        if (manifest.imagery[i].name == name) existing = i;
    if (existing < manifest.imagery.size() && !replace)
        return fail(
            fmt::format("{}: already has an imagery layer \"{}\" (--replace rebuilds it, "
                        "--name gives another)",
                        pyramid, name));
    // One draw composites at most four layers (runtime ImagerySelection.h): a fifth would
    // be stored and never drawn.
    constexpr std::size_t kMostLayers = 4;
    if (existing == manifest.imagery.size() && manifest.imagery.size() >= kMostLayers)
        return fail(
            fmt::format("{}: already has {} imagery layers, the most the draw "
                        "composites (--replace rebuilds one of them by its --name)",
                        pyramid, manifest.imagery.size()));
    const fs::path layerDir = fs::path(pyramid) / "imagery" / name;
    if (existing == manifest.imagery.size() && fs::exists(layerDir) && !replace)
        return fail(
            fmt::format("{}: exists, but the manifest lists no layer \"{}\" there "
                        "(--replace overwrites it)",
                        layerDir.string(), name));

    io::ImageryPlacement placement;
    placement.globe = manifest.globe.has_value();
    placement.georeference = manifest.georeference;
    placement.rasterWidth = manifest.layout.rasterWidth();
    placement.rasterHeight = manifest.layout.rasterHeight();
    placement.demExtent = demExtent;
    if (demExtent && placement.globe)
        return fail(
            fmt::format("--dem-extent: {} is a globe pyramid; the image must be "
                        "georeferenced",
                        pyramid));
    // Opened here first, so that a bad image is refused before anything is created.
    auto probe = io::openImageryImage(imagePath, placement);
    if (!probe) return fail(probe.error().message);
    bool probeTaken = false;
    const io::ImageryImageOpener opener =
        [&]() -> terrain::Result<std::unique_ptr<io::ImageryImage>> {
        if (!probeTaken) {
            probeTaken = true;
            return std::move(probe).value();
        }
        return io::openImageryImage(imagePath, placement);
    };
    io::ImageryBuildOptions options;
    options.name = name;
    options.input = imagePath;
    options.encoding = {lossless, quality};
    options.opacity = opacity;
    options.replaceExisting = replace;
    options.threads = threads;
    options.finestTexelPixels = finestTexelPixels;
    auto built = io::buildImageryLayer(pyramid, manifest, opener, options);
    if (!built) return fail(built.error().message);
    const io::ImageryBuildReport& report = built.value();
    const bool appended = existing == manifest.imagery.size();
    if (!appended)
        manifest.imagery[existing] = report.layer;
    else
        manifest.imagery.push_back(report.layer);
    if (terrain::Status written = io::writeManifest(pyramid, manifest); !written) {
        // A new layer's folder without its manifest entry would only be in the way.
        std::error_code ec;
        if (appended) fs::remove_all(layerDir, ec);
        return fail(written.error().message);
    }
    if (json) {
        const nlohmann::ordered_json j = {{"tool", "terrain-imagery"},
                                          {"pyramid", pyramid},
                                          {"image", imagePath},
                                          {"layer", name},
                                          {"folder", report.layer.folder},
                                          {"coarsestLevel", report.layer.coarsestLevel},
                                          {"finestLevel", report.layer.finestLevel},
                                          {"tiles", report.tiles},
                                          {"bytes", report.bytes},
                                          {"lossless", lossless},
                                          {"quality", quality},
                                          {"opacity", opacity},
                                          {"seconds", report.seconds}};
        std::printf("%s\n", j.dump(2).c_str());
    } else {
        fmt::print(
            "{}: imagery layer \"{}\" from {}: levels {} to {}, {} tiles, {:.2f} MB "
            "(WebP {}), built in {:.2f} s\n",
            pyramid, name, imagePath, report.layer.coarsestLevel, report.layer.finestLevel,
            report.tiles, static_cast<double>(report.bytes) * 1e-6,
            lossless ? "lossless" : fmt::format("quality {}", quality), report.seconds);
    }
    return 0;
}
