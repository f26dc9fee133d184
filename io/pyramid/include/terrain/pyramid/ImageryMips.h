// ImageryMips: the mip levels of an imagery tile (issue 47), made on the CPU by the I/O thread
// as it reads a tile (IoThread), so the render thread only uploads them (ImageryTilePool):
// each texel of a level is the alpha-weighted mean of the 2×2 texels under it, in linear
// light. The tile's texels are sRGB-encoded with straight alpha, so a plain mean would darken
// (sRGB) and would bleed the colour of transparent texels into their neighbours (straight
// alpha): weighting by alpha averages only what is seen, and a 2×2 block that is wholly
// transparent keeps the plain mean of its colours. This is the reference the GL test
// compares the uploaded mips with.
#pragma once

#include "terrain/pyramid/ImageryTile.h"

#include <array>
#include <cstdint>
#include <span>

namespace terrain::io {

/// One texel of a halved level: the alpha-weighted mean of `texels` (4 RGBA8 texels, sRGB
/// colour, straight alpha) in linear light, the plain mean of their colours when all four
/// are transparent; alpha the rounded mean. What halveImagery computes for each 2×2 block,
/// and what the imagery builder makes a coarser level's texels of (ImageryLayerBuilder), so
/// a tile's mip 1 and its parent's texels are the same bytes. Any thread.
void meanOfFourImageryTexels(const std::array<const std::uint8_t*, 4>& texels, std::uint8_t* out);

/// Halves `source`, `side` × `side` RGBA8 texels (side even, row-major; sRGB colour,
/// straight alpha), into `out`, (side / 2)² texels. Any thread.
void halveImagery(std::span<const std::uint8_t> source, int side, std::span<std::uint8_t> out);

/// Fills tile.mips with mips 1 … kImageryTileMips − 1 of tile.rgba (a present tile's
/// kImageryTileBytes: TERRAIN_ASSERT), each halving the one before; reuses tile.mips'
/// storage, so a recycled tile allocates nothing. Any thread.
void makeImageryMips(ImageryTile& tile);

/// sRGB encoding of a byte ↔ linear light in [0, 1] (IEC 61966-2-1), as GL_SRGB8_ALPHA8
/// samples decode it; srgbFromLinear rounds to the nearest byte. Any thread.
float linearFromSrgb(std::uint8_t encoded);
std::uint8_t srgbFromLinear(float linear);

}  // namespace terrain::io
