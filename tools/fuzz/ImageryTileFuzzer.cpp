// Fuzz target: an imagery layer's tile file (docs/imagery.md, "Tile files"), as
// terrain-inspect --verify and the I/O thread's ImageryTileReader decode it: the header, the
// tile table (offsets, sizes, ImageryTileInfo, the table's CRC-32), then every payload's
// CRC-32 and its WebP decode (libwebp). Then the same bytes as the file of a layer, read tile
// by tile through ImageryTileReader: a file the check accepts must read without an error.
#include "FuzzScratch.h"
#include "terrain/pyramid/ImageryLayerWriter.h"
#include "terrain/pyramid/ImageryTileReader.h"

#include <cmath>
#include <cstdint>

namespace {

namespace fs = std::filesystem;
using namespace terrain;

// A layer of one file: tile (1, 0, 0) opaque, (1, 1, 0) half transparent, (1, 0, 1) clear.
fs::path seedLayer(const std::string& name, const io::ImageryEncoding& encoding) {
    const fs::path dir = fuzz::scratch() / "seeds" / name;
    auto writer = io::ImageryLayerWriter::create(dir, encoding);
    if (!writer) fuzz::harnessFailure(writer.error().message);
    for (int t = 0; t < 3; ++t) {
        io::ImageryTile tile;
        tile.id = {1, t == 1 ? 1 : 0, t == 2 ? 1 : 0};
        tile.info.present = true;
        tile.rgba.resize(io::kImageryTileBytes);
        for (std::size_t i = 0; i < tile.rgba.size(); i += 4) {
            const auto texel = static_cast<double>(i / 4);
            tile.rgba[i] = static_cast<std::uint8_t>(128 + 100 * std::sin(texel * 0.001));
            tile.rgba[i + 1] = static_cast<std::uint8_t>(i / 1024);
            tile.rgba[i + 2] = 60;
            tile.rgba[i + 3] = t == 0 ? 255 : t == 1 ? static_cast<std::uint8_t>(i / 1024) : 0;
        }
        tile.info.opaque = t == 0;
        if (Status s = writer.value().writeTile(tile); !s) fuzz::harnessFailure(s.error().message);
    }
    if (Status s = writer.value().finish(true); !s) fuzz::harnessFailure(s.error().message);
    return dir;
}

// The layer the input is read as: layer.json listing L1/0/0.tiles, the input written there.
const fs::path& readLayer() {
    static const fs::path dir = seedLayer("read", {});
    return dir;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    fuzz::addSeed(seedLayer("lossy", {}) / "L1" / "0" / "0.tiles", "lossy.tiles");
    fuzz::addSeed(seedLayer("lossless", {.lossless = true}) / "L1" / "0" / "0.tiles",
                  "lossless.tiles");
    (void)readLayer();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::span<const std::uint8_t> bytes(data, size);
    const Status checked = io::checkImageryTileFile(bytes);
    fuzz::writeFile(readLayer() / "L1" / "0" / "0.tiles", bytes);
    auto reader = io::ImageryTileReader::open(readLayer(), 0, 1);
    fuzz::require(reader.ok(), "the harness's layer.json opens");
    io::ImageryTile tile;
    for (std::int64_t y = 0; y < 2; ++y)
        for (std::int64_t x = 0; x < 2; ++x) {
            const Status s = reader.value()->readTile({1, x, y}, tile);
            if (!s) {
                // The file's own group (1, 0, 0) was written into the header; a table of
                // another group is refused by the reader only.
                continue;
            }
            fuzz::require(!tile.info.present || tile.rgba.size() == io::kImageryTileBytes,
                          "a present tile has all its texels");
            fuzz::require(tile.info.present || tile.rgba.empty(), "an absent tile has none");
        }
    (void)checked;
    return 0;
}
