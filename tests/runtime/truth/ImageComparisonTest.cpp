// The image measures of accuracy (ImageComparison.h) on small hand-made images: RMSE and
// PSNR, cracks told apart from silhouettes, terrain the reference shows nowhere near
// (overdrawn), popping as the LOD's change beyond the
// reference's, and a LOD switch's change where both frames show terrain.
#include "terrain/runtime/ImageComparison.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace terrain::runtime {
namespace {

constexpr std::array<std::uint8_t, 3> kClear{255, 0, 255};

/// An image from rows of characters (row 0 first, as stored): '.' clear colour, 'T' grey
/// terrain; depth 1 for terrain, 0 for clear.
FrameImages image(const std::vector<std::string>& rows) {
    FrameImages img;
    img.height = static_cast<int>(rows.size());
    img.width = static_cast<int>(rows.front().size());
    for (const std::string& row : rows) {
        for (const char c : row) {
            const bool terrain = c == 'T';
            img.rgba.insert(img.rgba.end(), {terrain ? std::uint8_t{128} : kClear[0],
                                             terrain ? std::uint8_t{128} : kClear[1],
                                             terrain ? std::uint8_t{128} : kClear[2], 255});
            img.depth.push_back(terrain ? 1.0f : 0.0f);
        }
    }
    return img;
}

TEST(ImageComparison, RmseAndPsnr) {
    std::vector<std::uint8_t> a(4 * 100, 10), b = a;
    const ImageDifference same = compareImages(a, b);
    EXPECT_EQ(same.rmse, 0.0);
    EXPECT_EQ(same.psnrDb, kIdenticalPsnrDb);
    b[0] = 10 + 30;    // R of pixel 0
    b[4 * 7 + 2] = 0;  // B of pixel 7: −10
    b[3] = 0;          // alpha is ignored
    const ImageDifference d = compareImages(a, b);
    EXPECT_NEAR(d.rmse, std::sqrt((30.0 * 30.0 + 10.0 * 10.0) / 300.0), 1e-12);
    EXPECT_NEAR(d.psnrDb, 20.0 * std::log10(255.0 / d.rmse), 1e-12);
}

TEST(ImageComparison, CracksAreEnclosedAndSilhouettesReachTheSky) {
    const FrameImages reference = image({
        "TTTTTT",
        "TTTTTT",
        "TTTTTT",
        "TTTT..",
        "......",
    });
    const FrameImages lod = image({
        "TTTTTT",
        "TT.TTT",  // a crack: clear, enclosed by terrain
        "TTTTT.",  // a silhouette drawn too low: clear, touching the sky below-right
        "TTTT..",
        "......",
    });
    const UncoveredPixels u = countUncoveredPixels(lod, reference, kClear);
    EXPECT_EQ(u.uncovered, 2u);
    EXPECT_EQ(u.cracks, std::vector<std::size_t>{8});  // 6 · 1 + 2: the second row, column 2
    // A crack on the image border is still a crack (the border is not sky).
    const FrameImages border = image({
        ".TTTTT",
        "TTTTTT",
        "TTTTTT",
        "TTTT..",
        "......",
    });
    EXPECT_EQ(countUncoveredPixels(border, reference, kClear).cracks.size(), 1u);
    EXPECT_EQ(countUncoveredPixels(reference, reference, kClear).uncovered, 0u);
}

// A DEM's edge seen along its length: the silhouette runs askew to the pixel grid, and the
// LOD's, up to ε off the reference's, can leave a pixel clear with terrain on its four sides
// that reaches the sky through a corner (terrain-bench on an SRTM tile at --spacing 1 counted
// such pixels as cracks, issue 52). A notch, not a crack; a crack one pixel wide that runs
// diagonally to the silhouette still counts but for its last pixel.
TEST(ImageComparison, ASilhouettesNotchAtACornerIsNoCrack) {
    const FrameImages reference = image({
        "TTTTTTT",
        "TTTTTTT",
        "TTTTTTT",
        "TTTTTTT",
        "TTTTT..",
    });
    const FrameImages notch = image({
        "TTTTTTT",
        "TTTTTTT",
        "TTTTTTT",
        "TTTT.TT",  // clear: terrain left, right, above and below, the sky at its lower right
        "TTTTT..",
    });
    const UncoveredPixels n = countUncoveredPixels(notch, reference, kClear);
    EXPECT_EQ(n.uncovered, 1u);
    EXPECT_TRUE(n.cracks.empty());
    const FrameImages diagonal = image({
        "TTTTTTT",
        "T.TTTTT",
        "TT.TTTT",
        "TTT.TTT",
        "TTTT...",  // the line's last pixel (row 3, column 3) touches the sky at a corner
    });
    const UncoveredPixels d = countUncoveredPixels(diagonal, reference, kClear);
    EXPECT_EQ(d.uncovered, 4u);  // row 4, column 4 is clear in the reference too: sky
    EXPECT_EQ(d.cracks, (std::vector<std::size_t>{8, 16}));  // rows 1 and 2; not row 3
}

TEST(ImageComparison, OverdrawnIsTerrainTheReferenceShowsNowhereNear) {
    // The reference's terrain ends at row 2; the LOD's silhouette a row lower (its error
    // within ε = 1 px), and a wall hanging three rows below the outline at columns 5-6.
    const FrameImages reference = image({"TTTTTTTT",  //
                                         "TTTTTTTT",  //
                                         "TTTTTTTT",  //
                                         "........",  //
                                         "........",  //
                                         "........"});
    const FrameImages lod = image({"TTTTTTTT",  //
                                   "TTTTTTTT",  //
                                   "TTTTTTTT",  //
                                   "TTTTTTTT",  //
                                   ".....TT.",  //
                                   ".....TT."});
    EXPECT_EQ(countOverdrawnPixels(lod, reference, 0), 12u);
    EXPECT_EQ(countOverdrawnPixels(lod, reference, 1), 4u);  // the wall's lower two rows
    EXPECT_EQ(countOverdrawnPixels(lod, reference, 3), 0u);
    EXPECT_EQ(countOverdrawnPixels(reference, reference, 0), 0u);
    // The reference's own silhouette lower than the LOD's: uncovered, not overdrawn.
    EXPECT_EQ(countOverdrawnPixels(reference, lod, 0), 0u);
}

TEST(ImageComparison, PoppingIsTheLodChangeTheReferenceDoesNotShow) {
    const std::vector<std::uint8_t> still(4 * 10, 100);
    std::vector<std::uint8_t> popped = still;
    popped[0] = 160;  // one pixel's red changes by 60: its mean change is 20 levels
    // The reference did not change: all of the LOD's change is popping.
    EXPECT_NEAR(poppingLevels(still, popped, still, still), 20.0 / 10.0, 1e-12);
    EXPECT_NEAR(meanImageChange(still, popped), 2.0, 1e-12);
    // The reference changed the same way: no popping.
    EXPECT_EQ(poppingLevels(still, popped, still, popped), 0.0);
    // The reference changed more: floored at 0, never negative.
    std::vector<std::uint8_t> moved = still;
    moved[0] = 250;
    EXPECT_EQ(poppingLevels(still, popped, still, moved), 0.0);
    // Per pixel: a change elsewhere in the reference does not excuse this one.
    std::vector<std::uint8_t> elsewhere = still;
    elsewhere[4 * 5] = 160;
    EXPECT_NEAR(poppingLevels(still, popped, still, elsewhere), 2.0, 1e-12);
}

TEST(ImageComparison, LodSwitchIsTheChangeWhereBothShowTerrain) {
    const FrameImages held = image({"TTTT", "TT.."});
    FrameImages drawn = image({"TTTT", "TTTT"});
    // Terrain only the drawn frame covers (the held LOD culled it) is no switch.
    LodSwitchChange change = lodSwitchChange(held, drawn);
    EXPECT_EQ(change.meanLevels, 0.0);
    EXPECT_EQ(change.jumpShare, 0.0);
    // One of the 6 pixels both cover changes by 27 levels (red by 81): a jump.
    drawn.rgba[0] = 128 + 81;
    // Another by 6 levels (red by 18): a change, not a jump.
    drawn.rgba[4] = 128 + 18;
    change = lodSwitchChange(held, drawn);
    EXPECT_NEAR(change.meanLevels, (27.0 + 6.0) / 6.0, 1e-12);
    EXPECT_NEAR(change.jumpShare, 1.0 / 6.0, 1e-12);
    // Nothing covered by both: no change at all, not a division by zero.
    const FrameImages empty = image({"....", "...."});
    EXPECT_EQ(lodSwitchChange(empty, drawn).meanLevels, 0.0);
}

}  // namespace
}  // namespace terrain::runtime
