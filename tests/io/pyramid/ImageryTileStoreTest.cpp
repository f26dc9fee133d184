// Imagery tile files (ImageryLayerWriter, ImageryTileReader; docs/imagery.md): round trips
// (lossless exact, lossy within a PSNR bound), absent and transparent tiles, every damage
// to a file detected or harmless, and an unfinished writer leaving nothing behind.
#include "TempFolder.h"

#include "terrain/pyramid/ImageryLayerWriter.h"
#include "terrain/pyramid/ImageryTileReader.h"
#include "terrain/pyramid/ImageryTileSource.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>

namespace terrain::io {
namespace {

namespace fs = std::filesystem;

// A smooth picture with some detail and a transparent corner, different per tile.
ImageryTile picture(const PatchId& id, bool withTransparency) {
    ImageryTile tile;
    tile.id = id;
    tile.info.present = true;
    tile.rgba.resize(kImageryTileBytes);
    for (int r = 0; r < kImageryTileTexels; ++r)
        for (int c = 0; c < kImageryTileTexels; ++c) {
            const std::size_t at =
                (static_cast<std::size_t>(r) * kImageryTileTexels + static_cast<std::size_t>(c)) *
                4;
            const double phase = static_cast<double>(id.x * 7 + id.y * 3 + id.level);
            tile.rgba[at + 0] = static_cast<std::uint8_t>(128 + 100 * std::sin(c * 0.05 + phase));
            tile.rgba[at + 1] = static_cast<std::uint8_t>(128 + 100 * std::cos(r * 0.07));
            tile.rgba[at + 2] =
                static_cast<std::uint8_t>(128 + 100 * std::sin(r * 0.03 + c * 0.02));
            const bool clear = withTransparency && r + c < 60;
            tile.rgba[at + 3] = clear ? 0 : 255;
        }
    tile.info.opaque = !withTransparency;
    return tile;
}

double psnr(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b) {
    double sum = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        const double d = double(a[i]) - double(b[i]);
        sum += d * d;
    }
    const double mse = sum / static_cast<double>(a.size());
    return mse == 0.0 ? 99.0 : 10.0 * std::log10(255.0 * 255.0 / mse);
}

std::vector<PatchId> someTiles() {
    // Two groups of level 5, a root, tiles in both orders.
    return {{5, 17, 3}, {0, 0, 0}, {5, 1, 2}, {5, 0, 0}, {5, 16, 0}};
}

fs::path writeLayer(const fs::path& dir, const ImageryEncoding& encoding,
                    const std::vector<ImageryTile>& tiles) {
    Result<ImageryLayerWriter> writer = ImageryLayerWriter::create(dir, encoding);
    EXPECT_TRUE(writer.ok()) << writer.error().message;
    for (const ImageryTile& t : tiles) {
        const Status s = writer.value().writeTile(t);
        EXPECT_TRUE(s.ok()) << s.error().message;
    }
    const Status finished = writer.value().finish(false);
    EXPECT_TRUE(finished.ok()) << finished.error().message;
    return dir;
}

TEST(ImageryTileStore, LosslessRoundTripIsExact) {
    test::TempFolder temp;
    std::vector<ImageryTile> tiles;
    for (const PatchId& id : someTiles()) tiles.push_back(picture(id, id.x == 1));
    tiles[2].info.presentChildren = 0b1010;
    // The colour under alpha 0 too.
    tiles[2].rgba[0] = 77;
    const fs::path dir = writeLayer(temp.path() / "imagery" / "photo", {.lossless = true}, tiles);
    auto reader = ImageryTileReader::open(dir, 0, 6);
    ASSERT_TRUE(reader.ok()) << reader.error().message;
    ImageryTile back;
    for (const ImageryTile& t : tiles) {
        const Status s = reader.value()->readTile(t.id, back);
        ASSERT_TRUE(s.ok()) << s.error().message;
        EXPECT_EQ(back.info, t.info);
        EXPECT_TRUE(back.rgba == t.rgba) << t.id.level << " " << t.id.x << " " << t.id.y;
    }
    // Not written: absent (its file exists, and where none does), no error.
    for (const PatchId& id : {PatchId{5, 2, 2}, PatchId{5, 100, 100}, PatchId{3, 0, 0}}) {
        ASSERT_TRUE(reader.value()->readTile(id, back).ok());
        EXPECT_FALSE(back.info.present);
        EXPECT_TRUE(back.rgba.empty());
    }
    // Outside the layer's levels: an error naming the tile.
    const Status outside = reader.value()->readTile({7, 0, 0}, back);
    ASSERT_FALSE(outside.ok());
    EXPECT_NE(outside.error().message.find("level 7"), std::string::npos);
    EXPECT_EQ(reader.value()->index().presentTiles(), 5);
    std::int64_t checked = 0;
    const Status verified = reader.value()->verifyAll(checked);
    EXPECT_TRUE(verified.ok()) << verified.error().message;
    EXPECT_EQ(checked, 5);
}

TEST(ImageryTileStore, LossyRoundTripKeepsAlphaAndPsnr) {
    test::TempFolder temp;
    const std::vector<ImageryTile> tiles = {picture({0, 0, 0}, true)};
    const fs::path dir = writeLayer(temp.path() / "photo", {.quality = 85}, tiles);
    auto reader = ImageryTileReader::open(dir, 0, 0);
    ASSERT_TRUE(reader.ok()) << reader.error().message;
    ImageryTile back;
    ASSERT_TRUE(reader.value()->readTile({0, 0, 0}, back).ok());
    std::vector<std::uint8_t> colour(tiles[0].rgba.size()), colourBack(colour.size());
    for (std::size_t i = 0; i < colour.size(); i += 4) {
        const bool visible = tiles[0].rgba[i + 3] != 0;
        EXPECT_EQ(back.rgba[i + 3], tiles[0].rgba[i + 3]);  // alpha exact
        for (std::size_t k = 0; k < 3; ++k) {
            colour[i + k] = visible ? tiles[0].rgba[i + k] : 0;
            colourBack[i + k] = visible ? back.rgba[i + k] : 0;
        }
    }
    EXPECT_GT(psnr(colour, colourBack), 35.0);
    // Smaller than the texels by far.
    EXPECT_LT(reader.value()->index().bytes(), std::int64_t{kImageryTileBytes} / 4);
}

TEST(ImageryTileStore, TransparentTileStoresNoPayload) {
    test::TempFolder temp;
    ImageryTile clear;
    clear.id = {0, 0, 0};
    clear.info = {.present = true, .presentChildren = 1, .opaque = false};
    clear.rgba.assign(kImageryTileBytes, 0);
    const fs::path dir = writeLayer(temp.path() / "clear", {}, {clear});
    auto reader = ImageryTileReader::open(dir, 0, 1);
    ASSERT_TRUE(reader.ok());
    EXPECT_EQ(reader.value()->index().bytes(), 48 + 256 * 20);  // the table only
    ImageryTile back;
    ASSERT_TRUE(reader.value()->readTile({0, 0, 0}, back).ok());
    EXPECT_EQ(back.info, clear.info);
    EXPECT_EQ(back.rgba, clear.rgba);
}

TEST(ImageryTileStore, UnfinishedWriterLeavesNothing) {
    test::TempFolder temp;
    const fs::path dir = temp.path() / "imagery" / "photo";
    {
        Result<ImageryLayerWriter> writer = ImageryLayerWriter::create(dir, {});
        ASSERT_TRUE(writer.ok());
        ASSERT_TRUE(writer.value().writeTile(picture({0, 0, 0}, false)).ok());
    }
    EXPECT_FALSE(fs::exists(dir));
    EXPECT_FALSE(fs::exists(temp.path() / "imagery"));  // the folder it made, removed too
    fs::create_directories(temp.path() / "imagery");
    // An existing layer is not replaced unless asked, and is kept intact when refused.
    writeLayer(dir, {}, {picture({0, 0, 0}, false)});
    {
        Result<ImageryLayerWriter> writer = ImageryLayerWriter::create(dir, {});
        ASSERT_TRUE(writer.ok());
        const Status refused = writer.value().finish(false);
        ASSERT_FALSE(refused.ok());
        EXPECT_NE(refused.error().message.find("already exists"), std::string::npos);
    }
    EXPECT_TRUE(ImageryTileReader::open(dir, 0, 0).ok());
    EXPECT_EQ(
        std::distance(fs::directory_iterator(temp.path() / "imagery"), fs::directory_iterator()),
        1);
    {
        Result<ImageryLayerWriter> writer = ImageryLayerWriter::create(dir, {});
        ASSERT_TRUE(writer.ok());
        ASSERT_TRUE(writer.value().finish(true).ok());  // replaced by an empty layer
    }
    auto reader = ImageryTileReader::open(dir, 0, 0);
    ASSERT_TRUE(reader.ok());
    EXPECT_EQ(reader.value()->index().presentTiles(), 0);
}

std::vector<char> readBytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}
void writeBytes(const fs::path& p, const std::vector<char>& bytes, std::size_t count) {
    std::ofstream out(p, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(count));
}

// Reads every tile of the layer back: either an error naming the file, or exactly the
// tiles written.
void expectDetectedOrHarmless(const fs::path& dir, const fs::path& file,
                              const std::vector<ImageryTile>& tiles, const std::string& what) {
    auto reader = ImageryTileReader::open(dir, 0, 1);
    ASSERT_TRUE(reader.ok());
    ImageryTile back;
    bool detected = false;
    for (const ImageryTile& t : tiles) {
        const Status s = reader.value()->readTile(t.id, back);
        if (!s) {
            detected = true;
            EXPECT_NE(s.error().message.find(file.string()), std::string::npos)
                << what << ": " << s.error().message;
            continue;
        }
        ASSERT_EQ(back.info, t.info) << what;
        ASSERT_TRUE(back.rgba == t.rgba) << what;
    }
    std::int64_t checked = 0;
    const Status verified = reader.value()->verifyAll(checked);
    if (detected) {
        EXPECT_FALSE(verified.ok()) << what;
    }
}

TEST(ImageryTileStore, EveryDamageIsDetectedOrHarmless) {
    test::TempFolder temp;
    std::vector<ImageryTile> tiles = {picture({1, 0, 0}, false), picture({1, 1, 0}, true)};
    const fs::path dir = writeLayer(temp.path() / "photo", {.lossless = true}, tiles);
    const fs::path file = dir / "L1" / "0" / "0.tiles";
    const std::vector<char> good = readBytes(file);
    ASSERT_GT(good.size(), 48u + 256 * 20);
    // Every byte of the header and the table, and every 97th of the payloads, flipped.
    for (std::size_t at = 0; at < good.size(); at += (at < 48 + 256 * 20 ? 1 : 97)) {
        std::vector<char> bad = good;
        bad[at] = static_cast<char>(bad[at] ^ 0x5A);
        writeBytes(file, bad, bad.size());
        expectDetectedOrHarmless(dir, file, tiles, "flipped byte " + std::to_string(at));
    }
    // Every truncation at a few hundred lengths.
    for (std::size_t length = 0; length < good.size(); length += 1 + good.size() / 300) {
        writeBytes(file, good, length);
        auto reader = ImageryTileReader::open(dir, 0, 1);
        ASSERT_TRUE(reader.ok());
        ImageryTile back;
        const Status s = reader.value()->readTile(tiles[1].id, back);
        ASSERT_FALSE(s.ok()) << "truncated to " << length;
        EXPECT_NE(s.error().message.find(file.string()), std::string::npos) << s.error().message;
    }
    // Missing.
    fs::remove(file);
    auto reader = ImageryTileReader::open(dir, 0, 1);
    ASSERT_TRUE(reader.ok());
    ImageryTile back;
    const Status missing = reader.value()->readTile(tiles[0].id, back);
    ASSERT_FALSE(missing.ok());
    EXPECT_NE(missing.error().message.find("missing"), std::string::npos);
    EXPECT_NE(missing.error().message.find("level 1, x 0, y 0"), std::string::npos);
}

TEST(ImageryTileStore, OpenedThroughTheManifest) {
    test::TempFolder temp;
    writeLayer(temp.path() / "imagery" / "photo", {}, {picture({0, 0, 0}, false)});
    PyramidManifest m = PyramidManifest::forLayout(PyramidLayout::create(129, 129).value());
    ManifestImageryLayer layer;
    layer.name = "photo";
    layer.folder = "imagery/photo";
    layer.codec = "webp";
    m.imagery.push_back(layer);
    auto source = openImageryTiles(temp.path(), m, layer);
    ASSERT_TRUE(source.ok()) << source.error().message;
    ImageryTile back;
    ASSERT_TRUE(source.value()->readTile({0, 0, 0}, back).ok());
    EXPECT_TRUE(back.info.present);
    layer.folder = "imagery/none";
    const auto missing = openImageryTiles(temp.path(), m, layer);
    ASSERT_FALSE(missing.ok());
    EXPECT_NE(missing.error().message.find("\"photo\""), std::string::npos);
}

}  // namespace
}  // namespace terrain::io
