// ShadingTiles: the tiles above a drawn patch's own that its footprint-filtered normals read,
// with the patch's samples on each; a native tile's id names no tile above it.
#include "terrain/pyramid/NativeTiles.h"
#include "terrain/runtime/ShadingTiles.h"

#include <gtest/gtest.h>

#include <array>
#include <vector>

namespace terrain::runtime {
namespace {

constexpr int kQuads = 128;

// Every tile asked for is resident, on a layer of its own: what the tiles list is then up to
// shadingTilesOf alone.
std::array<ShadingTile, kShadingAncestors> listed(const DrawnTile& tile,
                                                  std::vector<io::PatchId>& asked) {
    std::array<ShadingTile, kShadingAncestors> out{};
    shadingTilesOf(
        tile, kQuads,
        [&](AncestorTile& a) -> std::optional<int> {
            asked.push_back(a.id);
            return 100 + static_cast<int>(asked.size());
        },
        out);
    return out;
}

TEST(ShadingTiles, AFacePatchListsItsAncestorsWithItsSamplesOnEach) {
    std::vector<io::PatchId> asked;
    const DrawnTile tile{.id = {12, 5, 6}, .layer = 7};
    const auto out = listed(tile, asked);
    ASSERT_EQ(asked.size(), std::size_t(kShadingAncestors));
    EXPECT_EQ(asked[0], (io::PatchId{11, 2, 3}));
    EXPECT_EQ(asked[1], (io::PatchId{10, 1, 1}));
    // Patch 5 is the odd half of its parent: its samples from the parent's 64th on, at half
    // steps; patch 6 the even half along y.
    EXPECT_FLOAT_EQ(out[0][0], 64.0f);
    EXPECT_FLOAT_EQ(out[0][1], 0.0f);
    EXPECT_FLOAT_EQ(out[0][2], 0.5f);
    EXPECT_FLOAT_EQ(out[0][3], 101.0f);
    // Two levels up: x = 5 is 1 mod 4 (a quarter in), y = 6 is 2 mod 4 (half way).
    EXPECT_FLOAT_EQ(out[1][0], 32.0f);
    EXPECT_FLOAT_EQ(out[1][1], 64.0f);
    EXPECT_FLOAT_EQ(out[1][2], 0.25f);
}

// A native tile's id is {kNativeLevelBase + grid, x, y}: its "parent" would be the previous
// grid's tile (another source's own samples), which a resident tile of that grid would have
// shaded it with. It lists itself, as a tile whose ancestors are not resident does.
TEST(ShadingTiles, ANativeTileListsNoTileAboveIt) {
    for (const int grid : {0, 1, 5}) {
        std::vector<io::PatchId> asked;
        const DrawnTile tile{.id = io::nativeTileId(grid, 5, 1), .layer = 9};
        const auto out = listed(tile, asked);
        EXPECT_TRUE(asked.empty()) << "grid " << grid << " asked for " << asked.size();
        for (const ShadingTile& entry : out) {
            EXPECT_FLOAT_EQ(entry[0], 0.0f);
            EXPECT_FLOAT_EQ(entry[1], 0.0f);
            EXPECT_FLOAT_EQ(entry[2], 1.0f);
            EXPECT_FLOAT_EQ(entry[3], 9.0f);
        }
    }
}

}  // namespace
}  // namespace terrain::runtime
