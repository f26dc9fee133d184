// SplitMix64: the 64-bit integer hash and seed sequence behind every random choice of the
// procedural terrain. Steele, Lea & Flood, "Fast splittable pseudorandom number
// generators", OOPSLA 2014; constants from Vigna's public-domain splitmix64.c.
#pragma once

#include <cstdint>

namespace terrain::io::detail {

/// The SplitMix64 finaliser: a bijective 64-bit mix with full avalanche.
constexpr std::uint64_t mix64(std::uint64_t z) {
    z = (z ^ (z >> 30U)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27U)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31U);
}

/// A deterministic stream of 64-bit values (the SplitMix64 generator).
class SplitMix64 {
public:
    explicit constexpr SplitMix64(std::uint64_t seed) : m_state(seed) {}

    constexpr std::uint64_t next() {
        m_state += 0x9E3779B97F4A7C15ULL;
        return mix64(m_state);
    }
    /// Uniform in [0, 1) from the top 53 bits.
    constexpr double uniform() { return static_cast<double>(next() >> 11U) * 0x1.0p-53; }
    constexpr double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }

private:
    std::uint64_t m_state;
};

}  // namespace terrain::io::detail
