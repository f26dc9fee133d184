// runtime::RoughnessQuadtree, Lee & Shin 2011's quadtree texture (CPU only): a plane has no
// roughness; σ bounds each block's five midpoint errors (Fig. 2) and is at least twice its
// children's (Eq. 3, Fig. 4); blocks overhanging a raster that is not 2^d + 1 a side are
// forced to split and the others are not; the height ranges hold every sample of their block.
#include "terrain/runtime/RoughnessQuadtree.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace terrain::test {
namespace {

using runtime::RoughnessQuadtree;

std::vector<float> roughHeights(int width, int height, unsigned seed) {
    std::mt19937 random(seed);
    std::uniform_real_distribution<float> noise(-3.0f, 3.0f);
    std::vector<float> h(static_cast<std::size_t>(width) * height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            h[static_cast<std::size_t>(y) * width + x] = 100.0f * std::sin(0.2f * float(x)) +
                                                         40.0f * std::cos(0.13f * float(y)) +
                                                         noise(random);
    return h;
}

template <typename Visit>
void forEachBlock(const RoughnessQuadtree& tree, Visit visit) {
    for (int level = 0; level < tree.depth(); ++level) {
        const int h = 1 << level;
        for (int by = 0; by < tree.blocksPerSide(level); ++by)
            for (int bx = 0; bx < tree.blocksPerSide(level); ++bx)
                visit(level, h, h + 2 * h * bx, h + 2 * h * by,
                      by * tree.blocksPerSide(level) + bx);
    }
}

TEST(RoughnessQuadtreeTest, APlaneHasNoRoughness) {
    constexpr int kSide = 33;
    std::vector<float> plane(kSide * kSide);
    for (int y = 0; y < kSide; ++y)
        for (int x = 0; x < kSide; ++x)
            plane[y * kSide + x] = 3.0f * float(x) - 2.0f * float(y) + 7.0f;
    auto tree = RoughnessQuadtree::build(kSide, kSide, plane);
    ASSERT_TRUE(tree) << tree.error().message;
    EXPECT_EQ(tree.value().depth(), 5);
    EXPECT_EQ(tree.value().side(), kSide);
    forEachBlock(tree.value(), [&](int, int, int cx, int cy, int) {
        EXPECT_EQ(tree.value().roughnessAt(cx, cy), 0.0f) << cx << "," << cy;
    });
}

TEST(RoughnessQuadtreeTest, RoughnessBoundsTheMidpointErrorsAndDoublesUpTheTree) {
    constexpr int kSide = 65;
    const std::vector<float> h = roughHeights(kSide, kSide, 3);
    auto built = RoughnessQuadtree::build(kSide, kSide, h);
    ASSERT_TRUE(built) << built.error().message;
    const RoughnessQuadtree& tree = built.value();
    const auto at = [&](int x, int y) { return h[static_cast<std::size_t>(y) * kSide + x]; };
    int blocks = 0;
    forEachBlock(tree, [&](int level, int s, int cx, int cy, int) {
        const float sigma = tree.roughnessAt(cx, cy);
        const float c00 = at(cx - s, cy - s), c10 = at(cx + s, cy - s), c01 = at(cx - s, cy + s),
                    c11 = at(cx + s, cy + s);
        EXPECT_GE(sigma, std::abs(at(cx, cy) - 0.5f * (c00 + c11)));
        EXPECT_GE(sigma, std::abs(at(cx, cy - s) - 0.5f * (c00 + c10)));
        EXPECT_GE(sigma, std::abs(at(cx, cy + s) - 0.5f * (c01 + c11)));
        EXPECT_GE(sigma, std::abs(at(cx - s, cy) - 0.5f * (c00 + c01)));
        EXPECT_GE(sigma, std::abs(at(cx + s, cy) - 0.5f * (c10 + c11)));
        if (level > 0) {
            for (const int dy : {-1, 1})
                for (const int dx : {-1, 1})
                    EXPECT_GE(sigma, 2.0f * tree.roughnessAt(cx + dx * s / 2, cy + dy * s / 2));
        }
        ++blocks;
    });
    EXPECT_EQ(blocks, 32 * 32 + 16 * 16 + 8 * 8 + 4 * 4 + 2 * 2 + 1);
}

TEST(RoughnessQuadtreeTest, BlocksOverhangingTheRasterAreForcedToSplit) {
    constexpr int kWidth = 21, kHeight = 11;  // padded to 33 × 33, d = 5
    auto built = RoughnessQuadtree::build(kWidth, kHeight, roughHeights(kWidth, kHeight, 4));
    ASSERT_TRUE(built) << built.error().message;
    const RoughnessQuadtree& tree = built.value();
    EXPECT_EQ(tree.side(), 33);
    int forced = 0, inside = 0;
    forEachBlock(tree, [&](int, int s, int cx, int cy, int) {
        const bool overhangs = cx + s > kWidth - 1 || cy + s > kHeight - 1;
        const float sigma = tree.roughnessAt(cx, cy);
        if (overhangs) {
            EXPECT_EQ(sigma, RoughnessQuadtree::kForceSplit) << cx << "," << cy;
            ++forced;
        } else {
            EXPECT_LT(sigma, RoughnessQuadtree::kForceSplit) << cx << "," << cy;
            ++inside;
        }
    });
    EXPECT_GT(forced, 0);
    EXPECT_EQ(inside, 10 * 5 + 5 * 2 + 2 * 1);  // 2×2, 4×4 and 8×8-quad blocks that fit
}

TEST(RoughnessQuadtreeTest, HeightRangesHoldEverySampleOfTheirBlock) {
    constexpr int kWidth = 40, kHeight = 27;
    const std::vector<float> h = roughHeights(kWidth, kHeight, 5);
    auto built = RoughnessQuadtree::build(kWidth, kHeight, h);
    ASSERT_TRUE(built) << built.error().message;
    const RoughnessQuadtree& tree = built.value();
    forEachBlock(tree, [&](int level, int s, int cx, int cy, int index) {
        const glm::vec2 range = tree.heightRange(level)[static_cast<std::size_t>(index)];
        for (int y = std::max(cy - s, 0); y <= std::min(cy + s, kHeight - 1); ++y)
            for (int x = std::max(cx - s, 0); x <= std::min(cx + s, kWidth - 1); ++x) {
                EXPECT_GE(h[static_cast<std::size_t>(y) * kWidth + x], range.x);
                EXPECT_LE(h[static_cast<std::size_t>(y) * kWidth + x], range.y);
            }
    });
}

TEST(RoughnessQuadtreeTest, RefusesARasterTooSmallForABlock) {
    const std::vector<float> one(1, 0.0f);
    auto tree = RoughnessQuadtree::build(1, 1, one);
    ASSERT_FALSE(tree);
    EXPECT_NE(tree.error().message.find("at least 2 × 2"), std::string::npos);
}

}  // namespace
}  // namespace terrain::test
