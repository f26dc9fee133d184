// ImageryMips: the mip levels of an imagery tile (issue 47), made on the CPU as the pool
// uploads a tile: each texel of a level is the alpha-weighted mean of the 2×2 texels under
// it, in linear light. The tile's texels are sRGB-encoded with straight alpha, so a plain
// mean would darken (sRGB) and would bleed the colour of transparent texels into their
// neighbours (straight alpha): weighting by alpha averages only what is seen, and a 2×2
// block that is wholly transparent keeps the plain mean of its colours. This is the
// reference the GL test compares the uploaded mips with.
#pragma once

#include <cstdint>
#include <span>

namespace terrain::cache {

/// Halves `source`, `side` × `side` RGBA8 texels (side even, row-major; sRGB colour,
/// straight alpha), into `out`, (side / 2)² texels. Any thread.
void halveImagery(std::span<const std::uint8_t> source, int side, std::span<std::uint8_t> out);

/// sRGB encoding of a byte ↔ linear light in [0, 1] (IEC 61966-2-1), as GL_SRGB8_ALPHA8
/// samples decode it; srgbFromLinear rounds to the nearest byte. Any thread.
float linearFromSrgb(std::uint8_t encoded);
std::uint8_t srgbFromLinear(float linear);

}  // namespace terrain::cache
