// ImageryMips: a 256-entry decode table. Encoding starts from a table of 4096 buckets of
// linear light (each holding the byte its lowest value encodes to) and steps up past the
// midpoints the value lies beyond: the nearest byte, the same as a binary search over the
// decode table (encode(decode(b)) == b), in a lookup and a step or two. The binary search
// per channel made the mips 2–4× the WebP decode on the I/O thread.
#include "terrain/pyramid/ImageryMips.h"

#include "terrain/base/Assert.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <span>

namespace terrain::io {
namespace {

constexpr int kBuckets = 4096;

struct SrgbTables {
    std::array<float, 256> decode{};
    std::array<std::uint8_t, kBuckets> bucketStart{};

    SrgbTables() {
        for (std::size_t i = 0; i < decode.size(); ++i) {
            const double c = static_cast<double>(i) / 255.0;
            decode[i] =
                static_cast<float>(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
        }
        for (int q = 0; q < kBuckets; ++q)
            bucketStart[static_cast<std::size_t>(q)] =
                nearestBySearch(static_cast<float>(q) / kBuckets);
    }

    // The nearer of the two decoded bytes around `linear` (the upper one on a tie).
    std::uint8_t nearestBySearch(float linear) const {
        const auto above = std::lower_bound(decode.begin(), decode.end(), linear);
        if (above == decode.begin()) return 0;
        if (above == decode.end()) return 255;
        const auto index = static_cast<std::size_t>(above - decode.begin());
        return static_cast<std::uint8_t>(linear - decode[index - 1] < *above - linear ? index - 1
                                                                                      : index);
    }

    std::uint8_t nearest(float linear) const {
        if (!(linear > 0.0f)) return 0;  // NaN too, as the search gives
        if (linear >= 1.0f) return 255;
        std::size_t b = bucketStart[static_cast<std::size_t>(linear * kBuckets)];
        // Up while the next byte is at least as near (the search's tie rule).
        while (b < 255 && !(linear - decode[b] < decode[b + 1] - linear)) ++b;
        return static_cast<std::uint8_t>(b);
    }
};

const SrgbTables& tables() {
    static const SrgbTables t;
    return t;
}

}  // namespace

float linearFromSrgb(std::uint8_t encoded) { return tables().decode[encoded]; }

std::uint8_t srgbFromLinear(float linear) { return tables().nearest(linear); }

void meanOfFourImageryTexels(const std::array<const std::uint8_t*, 4>& texels, std::uint8_t* out) {
    const std::array<float, 256>& decode = tables().decode;
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
