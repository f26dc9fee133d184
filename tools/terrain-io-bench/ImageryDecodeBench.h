// ImageryDecodeBench: how many tiles of an imagery layer one I/O thread decodes a second
// (issue 47): every tile of the layer, in a shuffled order, read and decoded through the
// layer's ImageryTileSource and given its mips by makeImageryMips, the two calls
// IoThread::readImagery makes, on the calling thread; the two timed apart.
#pragma once

#include "terrain/base/Result.h"

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

namespace terrain::tools {

struct ImageryDecodeOptions {
    std::filesystem::path pyramid;
    std::string layer;             ///< the manifest's layer name
    double seconds = 5.0;          ///< measure for at least this long (and at least one pass)
    std::size_t maxTiles = 20000;  ///< the first this many present tiles, coarsest first
    std::uint64_t seed = 1;        ///< of the shuffled order
};

struct ImageryDecodeFigures {
    std::size_t distinctTiles = 0;  ///< present tiles cycled over
    std::uint64_t tiles = 0;        ///< tiles decoded while measuring
    std::uint64_t fileBytes = 0;    ///< the layer's tile files (0 for a generated layer)
    std::int64_t indexTiles = 0;    ///< present tiles the layer's index lists (0: generated)
    double decodeS = 0.0;           ///< time in the source's readTile (read, CRC, WebP decode)
    double mipsS = 0.0;             ///< time in makeImageryMips
    double seconds() const { return decodeS + mipsS; }
};

/// Runs the measure. Errors: no such layer (the message lists the pyramid's), a tile that
/// cannot be read (names the file and the tile), a layer with no tile.
Result<ImageryDecodeFigures> measureImageryDecode(const ImageryDecodeOptions& options);

}  // namespace terrain::tools
