// ValdetaroTiles: Sobel of Sobel per finest patch, maxima per tile.
#include "terrain/runtime/ValdetaroTiles.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace terrain::runtime {

int valdetaroTileQuads(const io::PyramidLayout& layout) {
    return std::min(layout.patchQuads(), kValdetaroMaxFactor);
}

std::vector<float> sobelMagnitude(std::span<const float> grid, int width, int height) {
    std::vector<float> out(grid.size());
    const auto at = [&](int x, int y) {
        x = std::clamp(x, 0, width - 1);
        y = std::clamp(y, 0, height - 1);
        return static_cast<double>(
            grid[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                 static_cast<std::size_t>(x)]);
    };
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            // Eq. 6 as printed: D_x's kernel differences rows, D_y's columns; the magnitude
            // (Eq. 7) does not care which is which.
            const double dx = (at(x - 1, y + 1) + 2.0 * at(x, y + 1) + at(x + 1, y + 1)) -
                              (at(x - 1, y - 1) + 2.0 * at(x, y - 1) + at(x + 1, y - 1));
            const double dy = (at(x + 1, y - 1) + 2.0 * at(x + 1, y) + at(x + 1, y + 1)) -
                              (at(x - 1, y - 1) + 2.0 * at(x - 1, y) + at(x - 1, y + 1));
            out[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                static_cast<std::size_t>(x)] = static_cast<float>(std::sqrt(dx * dx + dy * dy));
        }
    }
    return out;
}

Result<ValdetaroTileGrid> analyseValdetaroTiles(io::PyramidReader& reader) {
    const io::PyramidLayout& layout = reader.layout();
    const int finest = layout.finestLevel();
    ValdetaroTileGrid grid;
    grid.tileQuads = valdetaroTileQuads(layout);
    const int tilesPerPatch = layout.patchQuads() / grid.tileQuads;
    grid.tilesX = static_cast<int>(layout.patchesX(finest)) * tilesPerPatch;
    grid.tilesY = static_cast<int>(layout.patchesY(finest)) * tilesPerPatch;
    grid.tiles.assign(static_cast<std::size_t>(grid.tilesX) * static_cast<std::size_t>(grid.tilesY),
                      ValdetaroTile{});
    const int side = layout.tileSamples();  // with the apron
    const int apron = layout.apronSamples();
    io::PatchRecord record;
    for (std::int64_t py = 0; py < layout.patchesY(finest); ++py) {
        for (std::int64_t px = 0; px < layout.patchesX(finest); ++px) {
            const io::PatchId id{finest, px, py};
            if (auto read = reader.readPatch(id, record); !read) return read.error();
            const std::vector<float> gradient = sobelMagnitude(record.heights, side, side);
            const std::vector<float> ham = sobelMagnitude(gradient, side, side);
            for (int ty = 0; ty < tilesPerPatch; ++ty) {
                for (int tx = 0; tx < tilesPerPatch; ++tx) {
                    ValdetaroTile tile;
                    tile.heightMax = -std::numeric_limits<float>::infinity();
                    // The tile's samples, its borders included (shared with its neighbours).
                    for (int row = 0; row <= grid.tileQuads; ++row) {
                        for (int column = 0; column <= grid.tileQuads; ++column) {
                            const std::size_t i =
                                static_cast<std::size_t>(ty * grid.tileQuads + row + apron) *
                                    static_cast<std::size_t>(side) +
                                static_cast<std::size_t>(tx * grid.tileQuads + column + apron);
                            tile.hamMax = std::max(tile.hamMax, ham[i]);
                            if (record.heights[i] > tile.heightMax) {
                                tile.heightMax = record.heights[i];
                                tile.maxColumn = column;
                                tile.maxRow = row;
                            }
                        }
                    }
                    const auto corner = [&](int column, int row) {
                        return static_cast<double>(
                            record.heights
                                [static_cast<std::size_t>(ty * grid.tileQuads + row + apron) *
                                     static_cast<std::size_t>(side) +
                                 static_cast<std::size_t>(tx * grid.tileQuads + column + apron)]);
                    };
                    const double fx = static_cast<double>(tile.maxColumn) / grid.tileQuads;
                    const double fy = static_cast<double>(tile.maxRow) / grid.tileQuads;
                    const int q = grid.tileQuads;
                    tile.baseAtMax = static_cast<float>(
                        (1.0 - fy) * ((1.0 - fx) * corner(0, 0) + fx * corner(q, 0)) +
                        fy * ((1.0 - fx) * corner(0, q) + fx * corner(q, q)));
                    const std::size_t t = static_cast<std::size_t>(py * tilesPerPatch + ty) *
                                              static_cast<std::size_t>(grid.tilesX) +
                                          static_cast<std::size_t>(px * tilesPerPatch + tx);
                    grid.tiles[t] = tile;
                }
            }
        }
    }
    return grid;
}

}  // namespace terrain::runtime
