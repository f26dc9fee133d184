// PatchIdHash: a hash of PatchId for the request queue's and the caches' hash maps.
#pragma once

#include "terrain/pyramid/PyramidLayout.h"

#include <cstddef>
#include <cstdint>

namespace terrain::io {

struct PatchIdHash {
    /// Bits given to each of x and y in the packed key; levels get the remaining six.
    static constexpr int kCoordinateBits = 29;

    /// Packs level, x and y into one 64-bit key and scrambles it with the splitmix64
    /// finalizer (a bijection), so ids with 0 ≤ level < 64 and 0 ≤ x, y < 2^29 never
    /// collide (on 64-bit size_t) and nearby patches still spread over all buckets. Bits
    /// outside those ranges are scrambled separately and xor-ed in, so larger ids still
    /// hash well; they are merely not guaranteed collision-free.
    std::size_t operator()(const PatchId& id) const noexcept {
        constexpr std::uint64_t kMask = (std::uint64_t{1} << kCoordinateBits) - 1;
        const auto x = static_cast<std::uint64_t>(id.x);
        const auto y = static_cast<std::uint64_t>(id.y);
        const auto level = static_cast<std::uint64_t>(static_cast<std::uint32_t>(id.level));
        const std::uint64_t packed = ((level & 63u) << (2 * kCoordinateBits)) |
                                     ((y & kMask) << kCoordinateBits) | (x & kMask);
        std::uint64_t h = mix(packed);
        const std::uint64_t highX = x >> kCoordinateBits;
        const std::uint64_t highY = y >> kCoordinateBits;
        const std::uint64_t highLevel = level >> 6;
        if ((highX | highY | highLevel) != 0) {  // never for ids in the collision-free range
            constexpr std::uint64_t kGolden = 0x9e3779b97f4a7c15u;
            h ^=
                mix(mix(highX + kGolden) ^ mix(highY + 2 * kGolden) ^ mix(highLevel + 3 * kGolden));
        }
        return static_cast<std::size_t>(h);
    }

    /// splitmix64's finalizer (Steele, Lea & Flood 2014): a bijection on 64-bit words.
    static constexpr std::uint64_t mix(std::uint64_t z) noexcept {
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9u;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebu;
        return z ^ (z >> 31);
    }
};

}  // namespace terrain::io
