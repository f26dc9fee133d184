// cache::ImageryTilePool on a real context: capacity from the budget and the sampler state
// (sRGB, three mips, trilinear, anisotropic, clamped), uploaded mips equal to the CPU box
// filter, the per-frame upload budget, eviction that never takes a tile the frame uses, and
// no layer leaked or mapped twice under a random storm.
#include "GlTestFixture.h"
#include "terrain/cache/ImageryTilePool.h"
#include "terrain/gl/DriverWorkarounds.h"
#include "terrain/gl/GlInfo.h"
#include "terrain/pyramid/ImageryMips.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <random>
#include <span>
#include <tuple>
#include <vector>

namespace terrain::test {
namespace {

using cache::ImageryTilePool;
using io::TileKey;

class ImageryTilePoolTest : public GlTest {
protected:
    static ImageryTilePool makePool(int layers, std::size_t uploadBudget) {
        auto created = ImageryTilePool::create(
            {.budgetBytes = ImageryTilePool::bytesPerLayer() * static_cast<std::size_t>(layers),
             .uploadBudgetBytesPerFrame = uploadBudget});
        EXPECT_TRUE(created) << (created ? "" : created.error().message);
        return std::move(created).value();
    }

    /// Texels of varied colour and alpha, whole 2×2 blocks transparent here and there.
    static io::ImageryTile randomTile(std::uint32_t seed) {
        std::mt19937 random(seed);
        io::ImageryTile tile;
        tile.info = {.present = true, .presentChildren = 5, .opaque = false};
        tile.rgba.resize(io::kImageryTileBytes);
        for (std::uint8_t& byte : tile.rgba) byte = static_cast<std::uint8_t>(random());
        const int side = io::kImageryTileTexels;
        for (int y = 0; y < side; y += 2)
            for (int x = 0; x < side; x += 2)
                if (random() % 5 == 0)
                    for (int t : {0, 1, side, side + 1})
                        tile.rgba[static_cast<std::size_t>((y * side + x + t) * 4 + 3)] = 0;
        io::makeImageryMips(tile);  // as the I/O thread does
        return tile;
    }

    static std::vector<std::uint8_t> readMip(const ImageryTilePool& pool, int layer, int mip) {
        const int side = io::kImageryTileTexels >> mip;
        std::vector<std::uint8_t> texels(static_cast<std::size_t>(side * side * 4));
        pool.texture().readBack({.level = mip, .layer = layer, .width = side, .height = side},
                                GL_RGBA, GL_UNSIGNED_BYTE,
                                std::as_writable_bytes(std::span(texels)));
        return texels;
    }

    static GLint textureParameter(const ImageryTilePool& pool, GLenum name) {
        GLint value = 0;
        glGetTextureParameteriv(pool.texture().id(), name, &value);
        return value;
    }
};

TEST_F(ImageryTilePoolTest, CapacityFromTheBudgetAndSamplerState) {
    const std::size_t layerBytes = ImageryTilePool::bytesPerLayer();
    EXPECT_EQ(layerBytes, std::size_t{(256 * 256 + 128 * 128 + 64 * 64) * 4});
    auto created = ImageryTilePool::create({.budgetBytes = 3 * layerBytes + layerBytes / 2});
    ASSERT_TRUE(created) << created.error().message;
    const ImageryTilePool& pool = created.value();
    EXPECT_EQ(pool.capacity(), 3);
    EXPECT_EQ(pool.layersFree(), 3);
    EXPECT_EQ(pool.texture().internalFormat(), static_cast<GLenum>(GL_SRGB8_ALPHA8));
    EXPECT_EQ(pool.texture().levels(), io::kImageryTileMips);
    EXPECT_EQ(pool.texture().width(), io::kImageryTileTexels);
    EXPECT_EQ(textureParameter(pool, GL_TEXTURE_MAX_LEVEL), io::kImageryTileMips - 1);
    EXPECT_EQ(textureParameter(pool, GL_TEXTURE_MIN_FILTER), GL_LINEAR_MIPMAP_LINEAR);
    EXPECT_EQ(textureParameter(pool, GL_TEXTURE_MAG_FILTER), GL_LINEAR);
    EXPECT_EQ(textureParameter(pool, GL_TEXTURE_WRAP_S), GL_CLAMP_TO_EDGE);
    EXPECT_EQ(textureParameter(pool, GL_TEXTURE_WRAP_T), GL_CLAMP_TO_EDGE);
    // What the context is worth filtering with: its maximum, or 1 on llvmpipe
    // (gl::textureAnisotropyWorthFiltering, DriverWorkarounds.h).
    const float driverMax = gl::textureAnisotropyWorthFiltering();
    EXPECT_EQ(pool.maxAnisotropy(), std::min(16.0f, driverMax));
    if (driverMax > 1.0f) {
        GLfloat anisotropy = 0.0f;
        glGetTextureParameterfv(pool.texture().id(), GL_TEXTURE_MAX_ANISOTROPY, &anisotropy);
        EXPECT_EQ(anisotropy, pool.maxAnisotropy());
    }
    EXPECT_EQ(pool.checkInvariants(), std::nullopt);

    auto tooSmall = ImageryTilePool::create({.budgetBytes = layerBytes - 1});
    ASSERT_FALSE(tooSmall);
    EXPECT_NE(tooSmall.error().message.find("below one imagery tile"), std::string::npos)
        << tooSmall.error().message;
}

TEST_F(ImageryTilePoolTest, UploadedMipsEqualTheAlphaWeightedBoxFilter) {
    ImageryTilePool pool = makePool(2, 0);
    pool.beginFrame();
    const io::ImageryTile tile = randomTile(7);
    const TileKey key{{3, 2, 1}, 1};
    const auto allocation = pool.allocateEvicting(key);
    ASSERT_TRUE(allocation);
    EXPECT_FALSE(pool.isResident(key));
    EXPECT_EQ(pool.info(key), nullptr);
    ASSERT_TRUE(pool.upload(key, tile));  // the first upload of a frame fits any budget
    EXPECT_TRUE(pool.isResident(key));
    ASSERT_NE(pool.info(key), nullptr);
    EXPECT_EQ(*pool.info(key), tile.info);

    std::vector<std::uint8_t> mip1(128 * 128 * 4);
    std::vector<std::uint8_t> mip2(64 * 64 * 4);
    io::halveImagery(tile.rgba, 256, mip1);
    io::halveImagery(mip1, 128, mip2);
    // Read back as stored: sRGB-encoded bytes, not converted.
    EXPECT_EQ(readMip(pool, allocation->layer, 0), tile.rgba);
    EXPECT_EQ(readMip(pool, allocation->layer, 1), mip1);
    EXPECT_EQ(readMip(pool, allocation->layer, 2), mip2);

    // The upload budget: a second tile this frame is refused (uploading nothing), and goes
    // next frame.
    const TileKey other{{3, 2, 2}, 0};
    ASSERT_TRUE(pool.allocateEvicting(other));
    EXPECT_FALSE(pool.upload(other, randomTile(8)));
    EXPECT_EQ(pool.frameStats().uploadsDeferred, 1);
    EXPECT_FALSE(pool.isResident(other));
    pool.beginFrame();
    EXPECT_TRUE(pool.upload(other, randomTile(8)));
    EXPECT_EQ(pool.frameStats().uploads, 1);
    EXPECT_EQ(pool.bytesUsed(), 2 * ImageryTilePool::bytesPerLayer());
    EXPECT_EQ(pool.checkInvariants(), std::nullopt);
}

TEST_F(ImageryTilePoolTest, EvictionNeverTakesATileUsedThisFrame) {
    ImageryTilePool pool = makePool(3, 1 << 30);
    pool.beginFrame();
    const std::vector<TileKey> keys = {TileKey{{1, 0, 0}, 0}, TileKey{{1, 1, 0}, 0},
                                       TileKey{{1, 0, 0}, 1}};
    for (const TileKey& key : keys) {
        const auto allocation = pool.allocateEvicting(key);
        ASSERT_TRUE(allocation);
        EXPECT_EQ(allocation->evicted, std::nullopt);
    }
    const TileKey fourth{{2, 0, 0}, 0};
    EXPECT_EQ(pool.allocateEvicting(fourth), std::nullopt) << "all used by this frame";

    pool.beginFrame();
    pool.touch(keys[0]);
    pool.touch(keys[2]);
    const auto allocation = pool.allocateEvicting(fourth);
    ASSERT_TRUE(allocation);
    EXPECT_EQ(allocation->evicted, std::optional<TileKey>(keys[1]));
    EXPECT_EQ(pool.layerOf(keys[1]), std::nullopt);
    EXPECT_EQ(pool.frameStats().evictions, 1);
    EXPECT_EQ(pool.allocateEvicting(TileKey{{2, 1, 0}, 0}), std::nullopt);
    EXPECT_EQ(pool.checkInvariants(), std::nullopt);
}

TEST_F(ImageryTilePoolTest, NoLayerLeaksUnderARandomStorm) {
    constexpr int kLayers = 9;
    ImageryTilePool pool = makePool(kLayers, 2 * ImageryTilePool::bytesPerLayer());
    std::mt19937 random(99);
    const io::ImageryTile tile = randomTile(1);
    using Model = std::map<std::tuple<int, std::int64_t, std::int64_t>, int>;  // key → layer
    Model model;
    const auto name = [](const TileKey& k) {
        return std::tuple<int, std::int64_t, std::int64_t>{k.imageryLayer, k.id.x, k.id.y};
    };
    for (int frame = 0; frame < 300; ++frame) {
        pool.beginFrame();
        std::vector<TileKey> usedThisFrame;
        for (int step = 0; step < 6; ++step) {
            const TileKey key{
                {5, static_cast<std::int64_t>(random() % 6), static_cast<std::int64_t>(0)},
                static_cast<int>(random() % 3)};
            const auto op = random() % 4;
            if (op < 2) {
                const auto allocation = pool.allocateEvicting(key);
                if (!allocation) {
                    // Only when every layer is used by this frame.
                    EXPECT_EQ(
                        static_cast<int>(usedThisFrame.size()) >= kLayers || pool.layersFree() == 0,
                        true);
                    continue;
                }
                if (allocation->evicted) {
                    for (const TileKey& used : usedThisFrame)
                        EXPECT_FALSE(used == *allocation->evicted) << "evicted a tile in use";
                    model.erase(name(*allocation->evicted));
                }
                model[name(key)] = allocation->layer;
                usedThisFrame.push_back(key);
                if (op == 0) pool.upload(key, tile);
            } else if (op == 2 && pool.layerOf(key)) {
                pool.touch(key);
                usedThisFrame.push_back(key);
            } else if (op == 3 && pool.layerOf(key)) {
                bool used = false;
                for (const TileKey& u : usedThisFrame) used = used || u == key;
                if (used) continue;  // the draw never releases what it uses
                pool.release(key);
                model.erase(name(key));
            }
        }
        ASSERT_EQ(pool.checkInvariants(), std::nullopt) << "frame " << frame;
        ASSERT_EQ(static_cast<std::size_t>(pool.layersUsed()), model.size());
        for (const auto& [k, layer] : model) {
            const TileKey key{{5, std::get<1>(k), std::get<2>(k)}, std::get<0>(k)};
            ASSERT_EQ(pool.layerOf(key), std::optional<int>(layer));
            ASSERT_EQ(pool.tileOnLayer(layer), std::optional<TileKey>(key));
        }
    }
    for (int layer = 0; layer < pool.capacity(); ++layer)
        if (const auto key = pool.tileOnLayer(layer)) pool.release(*key);
    EXPECT_EQ(pool.layersFree(), kLayers);
    EXPECT_EQ(pool.checkInvariants(), std::nullopt);
}

}  // namespace
}  // namespace terrain::test
