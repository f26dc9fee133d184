// 2-D gradient noise on a hashed integer lattice (Perlin, "Improving Noise", SIGGRAPH
// 2002: quintic fade, dot products with lattice gradients), evaluated a row of samples at
// a time: the lattice row is fixed along a row of samples, so each lattice corner is
// hashed once per row and the per-sample work is a few multiply-adds. Evaluating one
// sample is a row of one and runs the same arithmetic, so results never depend on the
// window a sample is computed in.
#pragma once

#include "terrain/source/SplitMix64.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace terrain::io::detail {

/// 64 unit gradients evenly spaced on the circle (more directions than Perlin's 8 keep
/// the lattice axes from showing in ridges).
struct GradientTable {
    std::array<double, 128> xy{};  // x0, y0, x1, y1, ...
    GradientTable();
};
/// The table, built on first use (so static initialisers elsewhere may use the noise).
const GradientTable& gradientTable();

/// One noise field: lattice position of sample (x, y) is
/// (x·scale + offsetX, y·scale + offsetY).
struct NoiseField {
    double scale = 1.0;  ///< Lattice cells per sample.
    double offsetX = 0.0;
    double offsetY = 0.0;
    std::uint64_t salt = 0;
};

/// floor() for |v| < 2^62 without a libm call: truncate, then step down for negatives.
inline std::int64_t floorToInt(double v) {
    auto i = static_cast<std::int64_t>(v);
    return (static_cast<double>(i) > v) ? i - 1 : i;
}

/// Reusable buffers for noiseRow (the gradients of the lattice columns a row crosses).
struct NoiseRowScratch {
    std::vector<double> topX, topY, bottomX, bottomY;
};

/// out[i] = noise of `field` at sample (xStart + i, y), in [−1, 1] (the 2-D bound √2/2
/// of Perlin noise with unit gradients, rescaled by √2), for i < count.
void noiseRow(const NoiseField& field, std::int64_t y, std::int64_t xStart, std::size_t count,
              double* out, NoiseRowScratch& scratch);

}  // namespace terrain::io::detail
