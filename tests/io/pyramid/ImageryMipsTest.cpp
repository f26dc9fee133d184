// io::halveImagery, the imagery mips' reference: sRGB bytes round-trip through linear
// light, a uniform block stays itself, transparent texels lend no colour, a wholly
// transparent block keeps the plain mean, and the mean is taken in linear light.
#include "terrain/pyramid/ImageryMips.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
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

// The encoder's bucket table against the plain definition, the nearer decoded byte (the upper
// on a tie), at a million values across [0, 1] and at every midpoint and its neighbours.
TEST(ImageryMipsTest, SrgbEncodingIsTheNearestByte) {
    std::array<float, 256> decoded{};
    for (int b = 0; b < 256; ++b)
        decoded[static_cast<std::size_t>(b)] = linearFromSrgb(static_cast<std::uint8_t>(b));
    const auto nearest = [&](float linear) {
        int best = 0;
        for (int b = 1; b < 256; ++b)
            if (!(linear - decoded[static_cast<std::size_t>(best)] <
                  decoded[static_cast<std::size_t>(b)] - linear))
                best = b;
        return static_cast<std::uint8_t>(best);
    };
    std::vector<float> values;
    for (int i = 0; i <= 1'000'000; ++i) values.push_back(static_cast<float>(i) / 1e6f);
    for (int b = 0; b < 255; ++b) {
        const float mid =
            (decoded[static_cast<std::size_t>(b)] + decoded[static_cast<std::size_t>(b) + 1]) /
            2.0f;
        values.insert(values.end(), {std::nextafter(mid, 0.0f), mid, std::nextafter(mid, 1.0f)});
    }
    int wrong = 0;
    for (const float v : values)
        if (srgbFromLinear(v) != nearest(v) && ++wrong < 5) ADD_FAILURE() << v;
    EXPECT_EQ(wrong, 0);
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
