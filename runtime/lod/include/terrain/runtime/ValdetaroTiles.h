// ValdetaroTiles: the height-map analysis of Valdetaro et al. 2011 (LodMethod::Valdetaro2011)
// done once, before the first frame, as the paper does it: the height acceleration map
// (HAM) is a Sobel operator applied to the magnitude of a Sobel operator over the heights
// (§4.1, §6.1, Eq. 6–7), and each tile of a flat grid keeps the four values §6.2 sends to
// the GPU: HAM_max, the maximum height h_max of its samples and where it lies.
//
// The finest level is read patch by patch (its one-sample apron gives the first Sobel its
// neighbours; the second takes its neighbours clamped at the patch's apron, the only
// difference from running both over the whole map), so memory stays one patch and the
// grid of tiles. CPU only.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/pyramid/PyramidReader.h"

#include <span>
#include <vector>

namespace terrain::runtime {

/// §6.2's texel: the four channels of one tile.
struct ValdetaroTile {
    float hamMax = 0.0f;     ///< HAM_max, Eq. 7 twice (unnormalised kernels, heights in metres)
    float heightMax = 0.0f;  ///< h_max, metres
    /// The tile's bilinear surface (from its corner samples) under h_max: the deviation
    /// h_max − baseAtMax is what T_min projects (§5.2).
    float baseAtMax = 0.0f;
    int maxColumn = 0;  ///< where h_max lies, samples from the tile's north-west corner
    int maxRow = 0;
};

struct ValdetaroTileGrid {
    int tileQuads = 0;  ///< samples a tile spans (the paper's tile size: one quad a texel at 64)
    int tilesX = 0;
    int tilesY = 0;
    std::vector<ValdetaroTile> tiles;  ///< row-major, rows running south

    const ValdetaroTile& at(int x, int y) const {
        return tiles[static_cast<std::size_t>(y) * static_cast<std::size_t>(tilesX) +
                     static_cast<std::size_t>(x)];
    }
};

/// The largest tessellation factor GL guarantees (GL_MAX_TESS_GEN_LEVEL ≥ 64), the paper's.
constexpr int kValdetaroMaxFactor = 64;

/// The tile size for a pyramid: 64 quads (one quad a sample at factor 64, §4.2), or the
/// whole patch when patches are smaller; it divides the patch.
int valdetaroTileQuads(const io::PyramidLayout& layout);

/// Eq. 6–7 over a width × height grid (row-major), borders clamped: the gradient magnitude
/// D = √(D_x² + D_y²) of every sample.
std::vector<float> sobelMagnitude(std::span<const float> grid, int width, int height);

/// The tiles of the pyramid's finest level (errors name the shard and the patch).
Result<ValdetaroTileGrid> analyseValdetaroTiles(io::PyramidReader& reader);

}  // namespace terrain::runtime
