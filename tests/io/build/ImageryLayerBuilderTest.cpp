// buildImageryLayer (issue 47) over a fake image placed on a planar pyramid's samples: the
// finest level follows the image's pixel, tiles exist where the image is (each root always),
// borders hold what the neighbour holds, coarse levels are low-passed (no aliasing), and an
// image beside the terrain is refused with nothing written.
#include "FakeImageryImage.h"
#include "TempFolder.h"

#include "terrain/build/ImageryLayerBuilder.h"
#include "terrain/pyramid/ImageryTileReader.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

namespace terrain::io {
namespace {

using test::fakeImageryOpener;
using Colour = test::ImageColour;

namespace fs = std::filesystem;
std::array<std::uint8_t, 4> texel(const ImageryTile& t, int column, int row) {
    const std::size_t at =
        (static_cast<std::size_t>(row) * kImageryTileTexels + static_cast<std::size_t>(column)) * 4;
    return {t.rgba[at], t.rgba[at + 1], t.rgba[at + 2], t.rgba[at + 3]};
}

// 513 × 513 samples, patches of 129: levels 0 … 2, 4 × 4 patches at the finest.
PyramidManifest planar() {
    return PyramidManifest::forLayout(PyramidLayout::create(513, 513).value());
}

ImageryBuildOptions lossless(const std::string& name) {
    ImageryBuildOptions o;
    o.name = name;
    o.input = name + ".tif";
    o.encoding.lossless = true;
    o.threads = 2;
    return o;
}

TEST(ImageryLayerBuilder, FinestLevelFollowsThePixelAndBordersMatch) {
    test::TempFolder pyramid;
    // Half a sample a pixel over the whole DEM: texels of ≤ 0.5 samples, 128 / 248 · 2^-l.
    const Colour smooth = [](std::int64_t x, std::int64_t y) {
        return std::array<std::uint8_t, 4>{static_cast<std::uint8_t>(x % 251),
                                           static_cast<std::uint8_t>(y % 241),
                                           static_cast<std::uint8_t>((x + y) % 199), 255};
    };
    const auto built =
        buildImageryLayer(pyramid.path(), planar(),
                          fakeImageryOpener(1026, 1026, 0.0, 0.0, 0.5, smooth), lossless("photo"));
    ASSERT_TRUE(built.ok()) << built.error().message;
    EXPECT_EQ(built.value().layer.coarsestLevel, 0);
    EXPECT_EQ(built.value().layer.finestLevel, 3);  // 128/248/2 = 0.26 ≤ 0.5 < 0.52
    EXPECT_EQ(built.value().layer.folder, "imagery/photo");
    auto reader = ImageryTileReader::open(pyramid.path() / "imagery" / "photo", 0, 3);
    ASSERT_TRUE(reader.ok()) << reader.error().message;
    EXPECT_EQ(reader.value()->index().presentTiles(), 1 + 4 + 16 + 64);
    ImageryTile left, right, below;
    for (int level = 1; level <= 3; ++level) {
        ASSERT_TRUE(reader.value()->readTile({level, 0, 0}, left).ok());
        ASSERT_TRUE(reader.value()->readTile({level, 1, 0}, right).ok());
        ASSERT_TRUE(reader.value()->readTile({level, 0, 1}, below).ok());
        EXPECT_TRUE(left.info.opaque);
        EXPECT_EQ(left.info.presentChildren, level < 3 ? 0b1111 : 0);
        // Stored texel 252 + k of a tile lies where texel 4 + k of its east neighbour does.
        int worst = 0;
        for (int k = -4; k < 4; ++k)
            for (int r = 0; r < kImageryTileTexels; ++r)
                for (int ch = 0; ch < 4; ++ch) {
                    const auto a = texel(left, 252 + k, r), b = texel(right, 4 + k, r);
                    const auto c = texel(left, r, 252 + k), d = texel(below, r, 4 + k);
                    worst = std::max({worst, std::abs(int(a[ch]) - int(b[ch])),
                                      std::abs(int(c[ch]) - int(d[ch]))});
                }
        EXPECT_LE(worst, 1) << "level " << level;
    }
}

TEST(ImageryLayerBuilder, CoarseLevelsAreLowPassed) {
    test::TempFolder pyramid;
    // A checkerboard of single pixels, a quarter sample each: at the root a texel spans
    // about 8 pixels, and must be grey, not a moiré of black and white.
    const Colour checker = [](std::int64_t x, std::int64_t y) {
        const std::uint8_t v = (x + y) % 2 == 0 ? 255 : 0;
        return std::array<std::uint8_t, 4>{v, v, v, 255};
    };
    const auto built = buildImageryLayer(pyramid.path(), planar(),
                                         fakeImageryOpener(2052, 2052, 0.0, 0.0, 0.25, checker),
                                         lossless("checker"));
    ASSERT_TRUE(built.ok()) << built.error().message;
    EXPECT_EQ(built.value().layer.finestLevel, 4);  // past the pyramid's finest, 2
    auto reader = ImageryTileReader::open(pyramid.path() / "imagery" / "checker", 0, 4);
    ASSERT_TRUE(reader.ok());
    ImageryTile root;
    ASSERT_TRUE(reader.value()->readTile({0, 0, 0}, root).ok());
    for (int r = 20; r < 230; r += 7)
        for (int c = 20; c < 230; c += 5)
            EXPECT_NEAR(texel(root, c, r)[0], 128, 8) << c << " " << r;
}

TEST(ImageryLayerBuilder, PartialImageMakesPartialLayer) {
    test::TempFolder pyramid;
    // One sample a pixel over the DEM's south-east quarter only.
    const Colour grey = [](std::int64_t, std::int64_t) {
        return std::array<std::uint8_t, 4>{90, 90, 90, 255};
    };
    const auto built = buildImageryLayer(pyramid.path(), planar(),
                                         fakeImageryOpener(200, 200, 300.0, 300.0, 1.0, grey),
                                         lossless("quarter"));
    ASSERT_TRUE(built.ok()) << built.error().message;
    EXPECT_EQ(built.value().layer.finestLevel, 2);
    auto reader = ImageryTileReader::open(pyramid.path() / "imagery" / "quarter", 0, 2);
    ASSERT_TRUE(reader.ok());
    ImageryTile tile;
    ASSERT_TRUE(reader.value()->readTile({0, 0, 0}, tile).ok());
    EXPECT_TRUE(tile.info.present);
    EXPECT_FALSE(tile.info.opaque);
    EXPECT_EQ(tile.info.presentChildren, 0b1000);  // only the south-east child
    EXPECT_EQ(texel(tile, 20, 20)[3], 0);          // north-west: clear
    EXPECT_EQ(texel(tile, 200, 200), (std::array<std::uint8_t, 4>{90, 90, 90, 255}));
    ASSERT_TRUE(reader.value()->readTile({1, 0, 0}, tile).ok());
    EXPECT_FALSE(tile.info.present);
    // Samples 300 … 500 at level 2 (128 samples a patch): patches 2 and 3 in each direction.
    for (std::int64_t y = 0; y < 4; ++y)
        for (std::int64_t x = 0; x < 4; ++x) {
            ASSERT_TRUE(reader.value()->readTile({2, x, y}, tile).ok());
            EXPECT_EQ(tile.info.present, x >= 2 && y >= 2) << x << " " << y;
        }
}

TEST(ImageryLayerBuilder, ImageBesideTheTerrainIsRefusedAndNothingWritten) {
    test::TempFolder pyramid;
    const Colour grey = [](std::int64_t, std::int64_t) {
        return std::array<std::uint8_t, 4>{90, 90, 90, 255};
    };
    const auto built =
        buildImageryLayer(pyramid.path(), planar(),
                          fakeImageryOpener(100, 100, 5000.0, 0.0, 1.0, grey), lossless("beside"));
    ASSERT_FALSE(built.ok());
    EXPECT_NE(built.error().message.find("does not overlap"), std::string::npos);
    EXPECT_NE(built.error().message.find("fake.tif"), std::string::npos);
    EXPECT_FALSE(fs::exists(pyramid.path() / "imagery"));
}

}  // namespace
}  // namespace terrain::io
