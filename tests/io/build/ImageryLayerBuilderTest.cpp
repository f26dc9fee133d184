// buildImageryLayer (issue 47) over a fake image placed on a planar pyramid's samples: the
// finest level follows the image's pixel, tiles exist where the image is (each root always),
// borders hold what the neighbour holds, coarse levels are low-passed (no aliasing), a
// parent holds its children's mip 1 (no step at a level change, plane and globe), and an
// image beside the terrain is refused with nothing written.
#include "FakeImageryImage.h"
#include "TempFolder.h"

#include "terrain/build/ImageryLayerBuilder.h"
#include "terrain/pyramid/GlobeLayout.h"
#include "terrain/pyramid/ImageryMips.h"
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
    // Level 2's texels, 128/248 = 0.516 samples, are 1.03 pixels: within the default 1.1.
    EXPECT_EQ(built.value().layer.finestLevel, 2);
    EXPECT_EQ(built.value().layer.folder, "imagery/photo");
    {
        // Never coarser than the pixel: level 3 (0.26 ≤ 0.5 < 0.52).
        test::TempFolder other;
        ImageryBuildOptions exact = lossless("photo");
        exact.finestTexelPixels = 1.0;
        const auto finer = buildImageryLayer(
            other.path(), planar(), fakeImageryOpener(1026, 1026, 0.0, 0.0, 0.5, smooth), exact);
        ASSERT_TRUE(finer.ok()) << finer.error().message;
        EXPECT_EQ(finer.value().layer.finestLevel, 3);
    }
    auto reader = ImageryTileReader::open(pyramid.path() / "imagery" / "photo", 0, 2);
    ASSERT_TRUE(reader.ok()) << reader.error().message;
    EXPECT_EQ(reader.value()->index().presentTiles(), 1 + 4 + 16);
    ImageryTile left, right, below;
    for (int level = 1; level <= 2; ++level) {
        ASSERT_TRUE(reader.value()->readTile({level, 0, 0}, left).ok());
        ASSERT_TRUE(reader.value()->readTile({level, 1, 0}, right).ok());
        ASSERT_TRUE(reader.value()->readTile({level, 0, 1}, below).ok());
        EXPECT_TRUE(left.info.opaque);
        EXPECT_EQ(left.info.presentChildren, level < 2 ? 0b1111 : 0);
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
    // about 8 pixels, and must be one grey, not a moiré of black and white. The finest
    // level's texels are 1.03 pixels: one point a texel aliased the checkerboard into a beat
    // 31 texels long, which the means kept up to the root (38 levels of spread); 2 × 2
    // points a texel do not.
    const Colour checker = [](std::int64_t x, std::int64_t y) {
        const std::uint8_t v = (x + y) % 2 == 0 ? 255 : 0;
        return std::array<std::uint8_t, 4>{v, v, v, 255};
    };
    const auto built = buildImageryLayer(pyramid.path(), planar(),
                                         fakeImageryOpener(2052, 2052, 0.0, 0.0, 0.25, checker),
                                         lossless("checker"));
    ASSERT_TRUE(built.ok()) << built.error().message;
    EXPECT_EQ(built.value().layer.finestLevel, 3);  // past the pyramid's finest, 2
    auto reader = ImageryTileReader::open(pyramid.path() / "imagery" / "checker", 0, 3);
    ASSERT_TRUE(reader.ok());
    ImageryTile root;
    ASSERT_TRUE(reader.value()->readTile({0, 0, 0}, root).ok());
    // One grey: the 2 × 2 means in linear light make it lighter than the bytes' mean (128),
    // as the eye sees a fine checkerboard.
    int lightest = 0, darkest = 255;
    for (int r = 20; r < 230; r += 7)
        for (int c = 20; c < 230; c += 5) {
            const auto t = texel(root, c, r);
            lightest = std::max<int>(lightest, t[0]);
            darkest = std::min<int>(darkest, t[0]);
            EXPECT_EQ(t[0], t[1]);
        }
    EXPECT_LE(lightest - darkest, 8);
    EXPECT_GE(darkest, 120);
    EXPECT_LE(lightest, 200);
}

TEST(ImageryLayerBuilder, PartialImageMakesPartialLayer) {
    test::TempFolder pyramid;
    // One sample a pixel over the DEM's south-east quarter only.
    const Colour grey = [](std::int64_t, std::int64_t) {
        return std::array<std::uint8_t, 4>{90, 90, 90, 255};
    };
    ImageryBuildOptions exact = lossless("quarter");
    exact.finestTexelPixels = 1.0;  // level 2, texels of 0.52 samples
    const auto built = buildImageryLayer(
        pyramid.path(), planar(), fakeImageryOpener(200, 200, 300.0, 300.0, 1.0, grey), exact);
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

TEST(ImageryLayerBuilder, AnImageOnTheDemsExtentCoversTheTerrainToItsEdges) {
    test::TempFolder pyramid;
    // Its outer edges on the DEM's first and last samples (terrain-imagery --dem-extent):
    // pixel x covers samples [0.5 · x, 0.5 · x + 0.5) of the 513 (0 … 512).
    const Colour wave = [](std::int64_t x, std::int64_t y) {
        return std::array<std::uint8_t, 4>{static_cast<std::uint8_t>((x * 5) % 256),
                                           static_cast<std::uint8_t>((y * 3) % 256), 60, 255};
    };
    const auto built =
        buildImageryLayer(pyramid.path(), planar(),
                          fakeImageryOpener(1024, 1024, 0.5, 0.5, 0.5, wave), lossless("edge"));
    ASSERT_TRUE(built.ok()) << built.error().message;
    const int finest = built.value().layer.finestLevel;
    auto reader = ImageryTileReader::open(pyramid.path() / "imagery" / "edge", 0, finest);
    ASSERT_TRUE(reader.ok()) << reader.error().message;
    // Every texel opaque, border included: the terrain's edge, filtered with the texels
    // past it, is drawn in the image's colour, not half in the tint underneath.
    ImageryTile tile;
    std::int64_t clear = 0, tiles = 0;
    for (int level = 0; level <= finest; ++level)
        for (std::int64_t y = 0; y < (std::int64_t{1} << level); ++y)
            for (std::int64_t x = 0; x < (std::int64_t{1} << level); ++x) {
                ASSERT_TRUE(reader.value()->readTile({level, x, y}, tile).ok());
                ASSERT_TRUE(tile.info.present) << level << " " << x << " " << y;
                ++tiles;
                EXPECT_TRUE(tile.info.opaque) << level << " " << x << " " << y;
                for (std::size_t at = 3; at < tile.rgba.size(); at += 4)
                    clear += tile.rgba[at] != 255 ? 1 : 0;
            }
    EXPECT_EQ(tiles, reader.value()->index().presentTiles());  // none past the DEM
    EXPECT_EQ(clear, 0);
}

// The runtime draws a tile's own mip 1 until the footprint asks for its parent, then the
// parent's texels (docs/imagery.md): where a parent lies over a child, its stored texels
// 2 + 124·c … must be the child's mip 1 byte for byte, border texels included, or the
// picture steps at the level change. Counts the texels that differ, over every present
// parent and child of `reader`'s levels coarsest … finest.
std::int64_t texelsUnlikeTheChildrensMip1(ImageryTileReader& reader, int coarsest, int finest,
                                          std::int64_t& compared) {
    constexpr int half = kImageryTileTexels / 2;
    std::int64_t unlike = 0;
    compared = 0;
    ImageryTile parent, child;
    for (const ImageryIndexLevel& l : reader.index().levels) {
        if (l.level < coarsest || l.level >= finest) continue;
        for (const ImageryIndexFile& f : l.files)
            for (std::int64_t y = f.y * 16; y < f.y * 16 + 16; ++y)
                for (std::int64_t x = f.x * 16; x < f.x * 16 + 16; ++x) {
                    if (!reader.readTile({l.level, x, y}, parent).ok() || !parent.info.present)
                        continue;
                    for (int c = 0; c < 4; ++c) {
                        if (!(parent.info.presentChildren & (1 << c))) continue;
                        const int cx = c & 1, cy = c >> 1;
                        EXPECT_TRUE(
                            reader.readTile({l.level + 1, 2 * x + cx, 2 * y + cy}, child).ok());
                        if (child.rgba.empty()) continue;
                        makeImageryMips(child);
                        const std::span<const std::uint8_t> mip1 = imageryMip(child, 1);
                        for (int j = 0; j < half; ++j)
                            for (int i = 0; i < half; ++i) {
                                const auto p = texel(parent, 2 + cx * 124 + i, 2 + cy * 124 + j);
                                const std::size_t at = (static_cast<std::size_t>(j) * half +
                                                        static_cast<std::size_t>(i)) *
                                                       4;
                                ++compared;
                                if (p != std::array<std::uint8_t, 4>{mip1[at], mip1[at + 1],
                                                                     mip1[at + 2], mip1[at + 3]})
                                    ++unlike;
                            }
                    }
                }
    }
    return unlike;
}

TEST(ImageryLayerBuilder, AParentHoldsItsChildrensMip1OnThePlane) {
    test::TempFolder pyramid;
    // Near the finest texel's Nyquist limit, and partial (the image ends inside the DEM): a
    // parent sampled afresh from the image is another picture than its children halved.
    const Colour wave = [](std::int64_t x, std::int64_t y) {
        const double v = 127.5 + 127.5 * std::sin(2.6 * static_cast<double>(x)) *
                                     std::cos(1.9 * static_cast<double>(y));
        return std::array<std::uint8_t, 4>{static_cast<std::uint8_t>(std::lround(v)),
                                           static_cast<std::uint8_t>((x * 7) % 256), 90, 255};
    };
    const auto built =
        buildImageryLayer(pyramid.path(), planar(),
                          fakeImageryOpener(900, 1000, 20.0, 0.0, 0.5, wave), lossless("wave"));
    ASSERT_TRUE(built.ok()) << built.error().message;
    const int finest = built.value().layer.finestLevel;
    auto reader = ImageryTileReader::open(pyramid.path() / "imagery" / "wave", 0, finest);
    ASSERT_TRUE(reader.ok()) << reader.error().message;
    std::int64_t compared = 0;
    EXPECT_EQ(texelsUnlikeTheChildrensMip1(*reader.value(), 0, finest, compared), 0);
    EXPECT_GE(compared, 16 * 128 * 128);
}

// A whole-Earth image in longitude and latitude, wrapping around in x.
class FakeEarthImage final : public ImageryImage {
public:
    FakeEarthImage(std::int64_t w, Colour colour) : m_w(w), m_colour(std::move(colour)) {}
    const std::string& name() const override { return m_name; }
    std::int64_t width() const override { return m_w; }
    std::int64_t height() const override { return m_w / 2; }
    bool wrapsColumns() const override { return true; }
    void toPixels(std::span<double> xs, std::span<double> ys) override {
        const double perDegree = static_cast<double>(m_w) / 360.0;
        for (std::size_t i = 0; i < xs.size(); ++i) {
            xs[i] = (xs[i] + 180.0) * perDegree;
            ys[i] = (90.0 - ys[i]) * perDegree;
        }
    }
    std::array<double, 2> toTerrain(double x, double y) override {
        const double perDegree = static_cast<double>(m_w) / 360.0;
        return {x / perDegree - 180.0, 90.0 - y / perDegree};
    }
    Status readBlocks(std::int64_t bx0, std::int64_t by0, int w, int h, int k,
                      std::span<std::uint8_t> rgba) override {
        return test::FakeImageryImage(m_w, m_w / 2, 0.0, 0.0, 1.0, m_colour)
            .readBlocks(bx0, by0, w, h, k, rgba);
    }

private:
    std::string m_name{"earth.tif"};
    std::int64_t m_w;
    Colour m_colour;
};

TEST(ImageryLayerBuilder, AParentHoldsItsChildrensMip1OnTheGlobe) {
    auto layout = globeLayout(2);
    ASSERT_TRUE(layout.ok());
    PyramidManifest m = PyramidManifest::forLayout(layout.value());
    m.formatVersion = PyramidManifest::kGlobeFormatVersion;
    m.globe = ManifestGlobe{};
    m.globe->faceFinestLevel = 2;
    m.georeference.crsKind = CrsKind::Geographic;
    // 2048 × 1024: 0.18° pixels, faces to level 2 (texels 0.09°, 1 pixel at most); parents
    // at face edges take the texels past the edge from their children's borders.
    const Colour bands = [](std::int64_t x, std::int64_t y) {
        return std::array<std::uint8_t, 4>{static_cast<std::uint8_t>((x * 37) % 256),
                                           static_cast<std::uint8_t>((y * 11) % 256),
                                           static_cast<std::uint8_t>(((x + y) / 3) % 256), 255};
    };
    ImageryImageOpener earth = [&]() -> Result<std::unique_ptr<ImageryImage>> {
        return std::unique_ptr<ImageryImage>(new FakeEarthImage(2048, bands));
    };
    // Texels at most the pixel (two levels made of means), and the default's 1.03 pixels
    // (one level, its texels of 2 × 2 points).
    for (const double finestTexelPixels : {1.0, ImageryBuildOptions{}.finestTexelPixels}) {
        test::TempFolder pyramid;
        ImageryBuildOptions options = lossless("earth");
        options.finestTexelPixels = finestTexelPixels;
        const auto built = buildImageryLayer(pyramid.path(), m, earth, options);
        ASSERT_TRUE(built.ok()) << built.error().message;
        const int root = ManifestGlobe::kLevelOffset, finest = built.value().layer.finestLevel;
        EXPECT_EQ(finest, root + (finestTexelPixels == 1.0 ? 2 : 1));
        auto reader = ImageryTileReader::open(pyramid.path() / "imagery" / "earth", root, finest);
        ASSERT_TRUE(reader.ok()) << reader.error().message;
        std::int64_t compared = 0;
        EXPECT_EQ(texelsUnlikeTheChildrensMip1(*reader.value(), root, finest, compared), 0)
            << finestTexelPixels;
        EXPECT_EQ(compared, (finestTexelPixels == 1.0 ? 6 * (4 + 16) : 6 * 4) * 128 * 128);
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
