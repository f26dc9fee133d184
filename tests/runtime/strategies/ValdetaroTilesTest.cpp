// runtime::ValdetaroTiles, the height analysis of Valdetaro et al. 2011 (§4.1, §6.1–6.2): the
// Sobel magnitude of a plane is its constant gradient and the height acceleration (Sobel of
// Sobel) of a plane is zero inside it; on a built pyramid every tile records its highest
// sample, where it lies, the tile's bilinear surface under it, and a larger HAM_max where
// the terrain bends (a spike) than where it is a plane.
#include "AccuracyScenes.h"
#include "TempFolder.h"
#include "terrain/pyramid/PyramidReader.h"
#include "terrain/runtime/ValdetaroTiles.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace terrain::test {
namespace {

TEST(ValdetaroTilesTest, SobelOfAPlaneIsItsGradientAndItsAccelerationIsZero) {
    constexpr int kSize = 12;
    std::vector<float> plane(kSize * kSize);
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x)
            plane[static_cast<std::size_t>(y * kSize + x)] =
                3.0f * static_cast<float>(x) + 5.0f * static_cast<float>(y);
    const std::vector<float> d = runtime::sobelMagnitude(plane, kSize, kSize);
    const std::vector<float> ham = runtime::sobelMagnitude(d, kSize, kSize);
    // Eq. 6: each kernel weighs 1, 2, 1 on the two sides two samples apart: 4 · 2 · slope.
    const double expected = std::hypot(4.0 * 2.0 * 3.0, 4.0 * 2.0 * 5.0);
    for (int y = 1; y < kSize - 1; ++y) {
        for (int x = 1; x < kSize - 1; ++x) {
            EXPECT_NEAR(d[static_cast<std::size_t>(y * kSize + x)], expected, 1e-4);
            if (x >= 2 && y >= 2 && x < kSize - 2 && y < kSize - 2) {
                EXPECT_NEAR(ham[static_cast<std::size_t>(y * kSize + x)], 0.0, 1e-3);
            }
        }
    }
}

TEST(ValdetaroTilesTest, TilesRecordTheirHighestSampleAndBendMoreAtASpike) {
    // A tilted plane with one 300 m spike: 257² samples in patches of 129 (2 × 2 tiles of
    // 64 quads each): a grid of 4 × 4 tiles.
    constexpr std::int64_t kSize = 257;
    constexpr std::int64_t kSpikeX = 150, kSpikeY = 40;
    FunctionDem dem(
        kSize, kSize, 10.0,
        [](std::int64_t x, std::int64_t y) {
            const float plane =
                100.0f + 0.5f * static_cast<float>(x) + 0.25f * static_cast<float>(y);
            return x == kSpikeX && y == kSpikeY ? plane + 300.0f : plane;
        },
        false);
    const TempFolder folder;
    const auto pyramid = buildScenePyramid(dem, folder, "spike", 129, 16);
    auto reader = io::PyramidReader::open(pyramid);
    ASSERT_TRUE(reader) << reader.error().message;
    auto grid = runtime::analyseValdetaroTiles(reader.value());
    ASSERT_TRUE(grid) << grid.error().message;
    const runtime::ValdetaroTileGrid& g = grid.value();
    EXPECT_EQ(g.tileQuads, 64);
    EXPECT_EQ(g.tilesX, 4);
    EXPECT_EQ(g.tilesY, 4);

    const runtime::ValdetaroTile& spike = g.at(kSpikeX / 64, kSpikeY / 64);
    const float spikeHeight = 100.0f + 0.5f * kSpikeX + 0.25f * kSpikeY + 300.0f;
    EXPECT_FLOAT_EQ(spike.heightMax, spikeHeight);
    EXPECT_EQ(spike.maxColumn, kSpikeX % 64);
    EXPECT_EQ(spike.maxRow, kSpikeY % 64);
    // The plane under the spike, from the tile's corners.
    EXPECT_NEAR(spike.baseAtMax, spikeHeight - 300.0f, 1e-3);

    // A plane tile far from the spike: its highest sample is its south-east corner (the
    // plane rises east and south), the plane is its own bilinear surface, nothing bends.
    const runtime::ValdetaroTile& flat = g.at(0, 3);
    EXPECT_EQ(flat.maxColumn, 64);
    EXPECT_EQ(flat.maxRow, 64);
    EXPECT_NEAR(flat.baseAtMax, flat.heightMax, 1e-3);
    EXPECT_GT(spike.hamMax, 100.0f * std::max(flat.hamMax, 1.0f));
}

}  // namespace
}  // namespace terrain::test
