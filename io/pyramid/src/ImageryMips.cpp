// ImageryMips: a 256-entry decode table; encoding picks the nearest table entry by binary
// search, so encode(decode(b)) == b and no pow() runs per texel.
#include "terrain/pyramid/ImageryMips.h"

#include "terrain/base/Assert.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <span>

namespace terrain::io {
namespace {

const std::array<float, 256>& decodeTable() {
    static const std::array<float, 256> table = [] {
        std::array<float, 256> t{};
        for (std::size_t i = 0; i < t.size(); ++i) {
            const double c = static_cast<double>(i) / 255.0;
            t[i] =
                static_cast<float>(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
        }
        return t;
    }();
    return table;
}

}  // namespace

float linearFromSrgb(std::uint8_t encoded) { return decodeTable()[encoded]; }

std::uint8_t srgbFromLinear(float linear) {
    const std::array<float, 256>& t = decodeTable();
    const auto above = std::lower_bound(t.begin(), t.end(), linear);
    if (above == t.begin()) return 0;
    if (above == t.end()) return 255;
    const auto index = static_cast<std::size_t>(above - t.begin());
    // The nearer of the two neighbours, in linear light.
    return static_cast<std::uint8_t>(linear - t[index - 1] < *above - linear ? index - 1 : index);
}

void meanOfFourImageryTexels(const std::array<const std::uint8_t*, 4>& texels, std::uint8_t* out) {
    const std::array<float, 256>& decode = decodeTable();
    std::array<float, 3> weighted{};  // Σ alpha · linear colour
    std::array<float, 3> plain{};     // Σ linear colour, for a transparent block
    unsigned alphaSum = 0;
    for (const std::uint8_t* texel : texels) {
        const auto alpha = static_cast<float>(texel[3]);
        alphaSum += texel[3];
        for (std::size_t c = 0; c < 3; ++c) {
            weighted[c] += alpha * decode[texel[c]];
            plain[c] += decode[texel[c]];
        }
    }
    for (std::size_t c = 0; c < 3; ++c)
        out[c] = srgbFromLinear(alphaSum > 0 ? weighted[c] / static_cast<float>(alphaSum)
                                             : plain[c] / 4.0f);
    out[3] = static_cast<std::uint8_t>((alphaSum + 2) / 4);  // rounded mean
}

void halveImagery(std::span<const std::uint8_t> source, int side, std::span<std::uint8_t> out) {
    TERRAIN_ASSERT(side >= 2 && side % 2 == 0, "halveImagery: the side must be even");
    const auto s = static_cast<std::size_t>(side);
    const std::size_t half = s / 2;
    TERRAIN_ASSERT(source.size() == s * s * 4 && out.size() == half * half * 4,
                   "halveImagery: buffer sizes do not match the side");
    for (std::size_t y = 0; y < half; ++y) {
        const std::uint8_t* upper = &source[2 * y * s * 4];
        const std::uint8_t* lower = upper + s * 4;
        for (std::size_t x = 0; x < half; ++x)
            meanOfFourImageryTexels(
                {upper + 8 * x, upper + 8 * x + 4, lower + 8 * x, lower + 8 * x + 4},
                &out[(y * half + x) * 4]);
    }
}

void makeImageryMips(ImageryTile& tile) {
    TERRAIN_ASSERT(tile.rgba.size() == kImageryTileBytes,
                   "makeImageryMips: a tile without its kImageryTileBytes of texels");
    tile.mips.resize(kImageryMipChainBytes);
    std::span<const std::uint8_t> above(tile.rgba);
    std::size_t offset = 0;
    for (int mip = 1; mip < kImageryTileMips; ++mip) {
        const std::span<std::uint8_t> level =
            std::span(tile.mips).subspan(offset, imageryMipBytes(mip));
        halveImagery(above, kImageryTileTexels >> (mip - 1), level);
        above = level;
        offset += level.size();
    }
}

}  // namespace terrain::io
