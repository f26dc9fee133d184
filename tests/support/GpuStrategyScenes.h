// The rough synthetic rasters and cameras the tests of the GPU-built LOD methods (Lee & Shin,
// Ripolles) fly: a raster with ridges, a step down its middle and noise; its geometry (1 m
// samples, unknown CRS); a camera above its centre.
#pragma once

#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/TerrainGeometry.h"

#include <gtest/gtest.h>

#include <glm/vec2.hpp>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

namespace terrain::test {

/// width × height heights, rows running south: ridges of 40 m, a step of `stepM` down the
/// middle column, ±2 m of noise from `seed`.
inline std::vector<float> roughHeights(int width, int height, unsigned seed, float stepM = 30.0f) {
    std::mt19937 random(seed);
    std::uniform_real_distribution<float> noise(-2.0f, 2.0f);
    std::vector<float> h(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            h[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
              static_cast<std::size_t>(x)] =
                40.0f * std::sin(0.15f * float(x)) * std::cos(0.11f * float(y)) +
                (x > width / 2 ? stepM : 0.0f) + noise(random);
    return h;
}

/// The manifest of a width × height raster of 33-sample patches (no file behind it).
inline io::PyramidManifest manifestOf(int width, int height) {
    auto layout = io::PyramidLayout::create(width, height, 33, 8, 4);
    EXPECT_TRUE(layout) << layout.error().message;
    return io::PyramidManifest::forLayout(layout.value());
}

inline runtime::TerrainGeometry geometryOf(int width, int height) {
    return runtime::TerrainGeometry(manifestOf(width, height));
}

/// `heightM` above the raster's centre moved by `offsetM`, looking north at `pitchDeg`.
inline runtime::Camera cameraOver(const runtime::TerrainGeometry& geometry, double heightM,
                                  double pitchDeg, glm::dvec2 offsetM = {0.0, 0.0}) {
    runtime::Camera c;
    const glm::dvec2 centre = geometry.worldAtFraction(0.5, 0.5);
    c.position = {centre.x + offsetM.x, centre.y + offsetM.y, heightM};
    c.pitch = pitchDeg * std::numbers::pi / 180.0;
    c.fovY = 1.2;
    c.viewportWidth = 320;
    c.viewportHeight = 240;
    return c;
}

}  // namespace terrain::test
