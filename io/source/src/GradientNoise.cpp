// Gradient noise along a row of samples (see GradientNoise.h).
#include "GradientNoise.h"

#include <cmath>

namespace terrain::io::detail {

// 16 directions of the first quadrant, at (i + 0.5)·360°/64, as integers ×1000 and
// normalised with sqrt (correctly rounded in IEEE 754, unlike cos and sin, so the table
// and every height are the same on every machine and libm).
GradientTable::GradientTable() {
    constexpr int kQuadrant[16][2] = {{999, 49},  {989, 147}, {970, 243}, {942, 337},
                                      {904, 428}, {858, 514}, {803, 596}, {741, 672},
                                      {672, 741}, {596, 803}, {514, 858}, {428, 904},
                                      {337, 942}, {243, 970}, {147, 989}, {49, 999}};
    for (std::size_t q = 0; q < 4; ++q) {
        for (std::size_t i = 0; i < 16; ++i) {
            double x = kQuadrant[i][0];
            double y = kQuadrant[i][1];
            for (std::size_t r = 0; r < q; ++r) {  // rotate by 90° q times
                const double t = x;
                x = -y;
                y = t;
            }
            const double length = std::sqrt(x * x + y * y);
            xy[2 * (q * 16 + i)] = x / length;
            xy[2 * (q * 16 + i) + 1] = y / length;
        }
    }
}

const GradientTable& gradientTable() {
    static const GradientTable table;
    return table;
}

namespace {

inline double fade(double t) {  // Perlin 2002: 6t^5 − 15t^4 + 10t^3
    return t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
}

// Must match the per-sample expression in noiseRow's loop.
inline double latticeX(const NoiseField& f, std::int64_t x) {
    return static_cast<double>(x) * f.scale + f.offsetX;
}

}  // namespace

void noiseRow(const NoiseField& field, std::int64_t y, std::int64_t xStart, std::size_t count,
              double* out, NoiseRowScratch& scratch) {
    if (count == 0) return;
    const double py = static_cast<double>(y) * field.scale + field.offsetY;
    const std::int64_t iy = floorToInt(py);
    const double ty = py - static_cast<double>(iy);
    const double v = fade(ty);
    // x·scale + offset is monotonic in x after rounding, so every sample's cell lies
    // between the first and the last sample's.
    const std::int64_t firstColumn = floorToInt(latticeX(field, xStart));
    const std::int64_t lastColumn =
        floorToInt(latticeX(field, xStart + static_cast<std::int64_t>(count) - 1)) + 1;
    const auto columns = static_cast<std::size_t>(lastColumn - firstColumn + 1);
    scratch.topX.resize(columns);
    scratch.topY.resize(columns);
    scratch.bottomX.resize(columns);
    scratch.bottomY.resize(columns);
    // Corner hash: mix(mix(salt ^ iy) ^ ix); the row part is shared by a whole row.
    const std::uint64_t topKey = mix64(field.salt ^ static_cast<std::uint64_t>(iy));
    const std::uint64_t bottomKey = mix64(field.salt ^ static_cast<std::uint64_t>(iy + 1));
    const std::array<double, 128>& gradients = gradientTable().xy;
    for (std::size_t c = 0; c < columns; ++c) {
        const auto ix = static_cast<std::uint64_t>(firstColumn + static_cast<std::int64_t>(c));
        // The top 6 bits pick one of 64 gradients. y·(ty − cornerY) is folded in here.
        const std::size_t top = static_cast<std::size_t>(mix64(topKey ^ ix) >> 58U) * 2;
        const std::size_t bottom = static_cast<std::size_t>(mix64(bottomKey ^ ix) >> 58U) * 2;
        scratch.topX[c] = gradients[top];
        scratch.topY[c] = gradients[top + 1] * ty;
        scratch.bottomX[c] = gradients[bottom];
        scratch.bottomY[c] = gradients[bottom + 1] * (ty - 1.0);
    }
    // Locals: `out` could alias the field as far as the compiler knows.
    const double scale = field.scale;
    const double offsetX = field.offsetX;
    const double* topX = scratch.topX.data();
    const double* topY = scratch.topY.data();
    const double* bottomX = scratch.bottomX.data();
    const double* bottomY = scratch.bottomY.data();
    for (std::size_t i = 0; i < count; ++i) {
        const double px =
            static_cast<double>(xStart + static_cast<std::int64_t>(i)) * scale + offsetX;
        const std::int64_t ix = floorToInt(px);
        const auto c = static_cast<std::size_t>(ix - firstColumn);
        const double tx = px - static_cast<double>(ix);
        const double n00 = topX[c] * tx + topY[c];
        const double n10 = topX[c + 1] * (tx - 1.0) + topY[c + 1];
        const double n01 = bottomX[c] * tx + bottomY[c];
        const double n11 = bottomX[c + 1] * (tx - 1.0) + bottomY[c + 1];
        const double u = fade(tx);
        const double nx0 = n00 + u * (n10 - n00);
        const double nx1 = n01 + u * (n11 - n01);
        out[i] = (nx0 + v * (nx1 - nx0)) * 1.4142135623730951;
    }
}

}  // namespace terrain::io::detail
