// io::halveImagery, the imagery mips' reference: sRGB bytes round-trip through linear
// light, a uniform block stays itself, transparent texels lend no colour, a wholly
// transparent block keeps the plain mean, and the mean is taken in linear light.
#include "terrain/pyramid/ImageryMips.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <vector>

namespace terrain::io {
namespace {

std::array<std::uint8_t, 4> halveBlock(const std::array<std::array<std::uint8_t, 4>, 4>& block) {
    // A 2 × 2 image: texels (0,0), (1,0), (0,1), (1,1).
    std::vector<std::uint8_t> source;
    for (const auto& texel : block) source.insert(source.end(), texel.begin(), texel.end());
    std::vector<std::uint8_t> out(4);
    halveImagery(source, 2, out);
    return {out[0], out[1], out[2], out[3]};
}

TEST(ImageryMipsTest, SrgbBytesRoundTripThroughLinearLight) {
    for (int b = 0; b < 256; ++b) {
        const auto byte = static_cast<std::uint8_t>(b);
        EXPECT_EQ(srgbFromLinear(linearFromSrgb(byte)), byte);
    }
    EXPECT_EQ(srgbFromLinear(-1.0f), 0);
    EXPECT_EQ(srgbFromLinear(2.0f), 255);
    EXPECT_NEAR(linearFromSrgb(188), 0.5, 0.003);  // sRGB 188 is about half the light
}

TEST(ImageryMipsTest, AlphaWeightsTheColoursInLinearLight) {
    using T = std::array<std::uint8_t, 4>;
    EXPECT_EQ(halveBlock(
                  {T{10, 200, 30, 77}, T{10, 200, 30, 77}, T{10, 200, 30, 77}, T{10, 200, 30, 77}}),
              (T{10, 200, 30, 77}));
    // One opaque red texel among transparent green ones: red, a quarter covered.
    EXPECT_EQ(halveBlock({T{255, 0, 0, 255}, T{0, 255, 0, 0}, T{0, 255, 0, 0}, T{0, 255, 0, 0}}),
              (T{255, 0, 0, 64}));
    // Wholly transparent: the plain mean (in linear light) of the colours.
    const T clear = halveBlock({T{255, 0, 0, 0}, T{255, 0, 0, 0}, T{0, 0, 0, 0}, T{0, 0, 0, 0}});
    EXPECT_EQ(clear, (T{188, 0, 0, 0}));
    // Black and white, opaque: half the light is sRGB 188, not 128.
    EXPECT_EQ(halveBlock(
                  {T{0, 0, 0, 255}, T{255, 255, 255, 255}, T{0, 0, 0, 255}, T{255, 255, 255, 255}}),
              (T{188, 188, 188, 255}));
}

}  // namespace
}  // namespace terrain::io
