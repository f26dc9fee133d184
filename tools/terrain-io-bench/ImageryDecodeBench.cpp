// ImageryDecodeBench: the layer's present tiles found by walking its quadtree from the root
// tiles (each tile says which children exist), read once to warm the page cache, then cycled
// over in a shuffled order with each call timed.
#include "ImageryDecodeBench.h"

#include "terrain/globe/CubeSphere.h"
#include "terrain/pyramid/GlobeLayout.h"
#include "terrain/pyramid/ImageryLayerIndex.h"
#include "terrain/pyramid/ImageryMips.h"
#include "terrain/pyramid/ImageryTileSource.h"
#include "terrain/pyramid/PyramidManifest.h"

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <memory>
#include <random>
#include <vector>

namespace terrain::tools {
namespace {

using Clock = std::chrono::steady_clock;

double secondsBetween(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double>(b - a).count();
}

/// The layer's root tiles: the plane's coarsest level, or the six cube faces.
std::vector<io::PatchId> rootTiles(const io::PyramidManifest& manifest,
                                   const io::ManifestImageryLayer& layer) {
    std::vector<io::PatchId> roots;
    if (manifest.globe) {
        for (int face = 0; face < globe::kCubeFaces; ++face)
            roots.push_back(io::layoutPatchOf({face, 0, 0, 0}));
        return roots;
    }
    const int level = layer.coarsestLevel;
    for (std::int64_t y = 0; y < io::planarImageryTilesY(manifest.layout, level); ++y)
        for (std::int64_t x = 0; x < io::planarImageryTilesX(manifest.layout, level); ++x)
            roots.push_back({level, x, y});
    return roots;
}

}  // namespace

Result<ImageryDecodeFigures> measureImageryDecode(const ImageryDecodeOptions& options) {
    auto manifest = io::readManifest(options.pyramid);
    if (!manifest) return manifest.error();
    const auto& layers = manifest.value().imagery;
    const auto layer = std::find_if(layers.begin(), layers.end(),
                                    [&](const auto& l) { return l.name == options.layer; });
    if (layer == layers.end()) {
        std::string names;
        for (const auto& l : layers) names += (names.empty() ? "" : ", ") + l.name;
        return Error{fmt::format("{}: no imagery layer \"{}\" (the pyramid has {})",
                                 options.pyramid.string(), options.layer,
                                 names.empty() ? "none" : names)};
    }
    auto opened = io::openImageryTiles(options.pyramid, manifest.value(), *layer);
    if (!opened) return opened.error();
    io::ImageryTileSource& source = *opened.value();

    ImageryDecodeFigures figures;
    if (layer->kind == io::ManifestImageryLayer::kStoredKind) {
        auto index = io::readImageryIndex(options.pyramid / layer->folder);
        if (!index) return index.error();
        figures.fileBytes = static_cast<std::uint64_t>(index.value().bytes());
        figures.indexTiles = index.value().presentTiles();
    }

    // Every present tile, coarsest first (a tile's children are listed after it), read once:
    // the page cache holds the files, and every tile is known to read.
    io::ImageryTile tile;
    std::vector<io::PatchId> ids = rootTiles(manifest.value(), *layer);
    std::vector<io::PatchId> present;
    for (std::size_t next = 0; next < ids.size() && present.size() < options.maxTiles; ++next) {
        const io::PatchId id = ids[next];
        if (Status read = source.readTile(id, tile); !read) return read.error();
        if (!tile.info.present) continue;
        present.push_back(id);
        if (id.level == layer->finestLevel) continue;
        for (int c = 0; c < 4; ++c)
            if ((tile.info.presentChildren >> c) & 1)
                ids.push_back({id.level + 1, 2 * id.x + (c & 1), 2 * id.y + (c >> 1)});
    }
    if (present.empty())
        return Error{fmt::format("{}: imagery layer \"{}\" has no tile", options.pyramid.string(),
                                 options.layer)};
    // The walk from the roots finds every tile the index lists, or the layer is damaged.
    if (figures.indexTiles > 0 && present.size() < options.maxTiles &&
        static_cast<std::int64_t>(present.size()) != figures.indexTiles)
        return Error{fmt::format(
            "{}: imagery layer \"{}\": {} tiles under its roots, but its "
            "layer.json lists {}",
            options.pyramid.string(), options.layer, present.size(), figures.indexTiles)};
    std::shuffle(present.begin(), present.end(), std::mt19937_64(options.seed));
    figures.distinctTiles = present.size();

    // Whole passes over the shuffled tiles until the time is spent, each call timed apart.
    do {
        for (const io::PatchId& id : present) {
            const auto start = Clock::now();
            if (Status read = source.readTile(id, tile); !read) return read.error();
            const auto decoded = Clock::now();
            io::makeImageryMips(tile);
            const auto done = Clock::now();
            figures.decodeS += secondsBetween(start, decoded);
            figures.mipsS += secondsBetween(decoded, done);
            ++figures.tiles;
        }
    } while (figures.seconds() < options.seconds);
    return figures;
}

}  // namespace terrain::tools
