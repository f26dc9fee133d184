// TerrainViewChecks: what the crack and hole tests share: camera poses whose whole view is
// terrain, waiting for the root tile, and a count of the pixels still showing the clear
// colour (magenta, which the terrain shading never produces) after a draw.
#pragma once

#include "terrain/gl/Framebuffer.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/TerrainGeometry.h"
#include "terrain/runtime/TerrainSession.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <vector>

namespace terrain::test {

/// The clear colour of the crack and hole tests: pure magenta.
inline constexpr std::array<float, 4> kHoleColor{1.0f, 0.0f, 1.0f, 1.0f};

/// A pose whose every pixel sees terrain: above the DEM's interior and higher than its
/// highest sample, pitched between −35° and −90°, all four corner rays meeting the plane
/// z = minHeight inside the DEM rectangle. Since the camera is above the surface and each
/// ray reaches the plane (at or below the surface) over the DEM, it crosses the terrain.
inline runtime::Camera randomFullView(const runtime::TerrainGeometry& g, int widthPx, int heightPx,
                                      std::mt19937_64& random) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const double lastColumn = static_cast<double>(g.layout().rasterWidth() - 1);
    const double lastRow = static_cast<double>(g.layout().rasterHeight() - 1);
    const double floorM = g.minHeight() - 1.0;  // margin below the lowest sample
    const double reliefM = std::max(g.maxHeight() - g.minHeight(), 1.0);
    for (int attempt = 0; attempt < 100000; ++attempt) {
        runtime::Camera c;
        c.viewportWidth = widthPx;
        c.viewportHeight = heightPx;
        c.fovY = 0.9;
        const double fx = 0.05 + 0.9 * u(random), fy = 0.05 + 0.9 * u(random);
        c.position = {g.worldAtFraction(fx, fy),
                      g.maxHeight() + 2.0 + reliefM * 1.5 * u(random) * u(random)};
        c.yaw = 2.0 * std::numbers::pi * u(random);
        c.pitch = -(35.0 + 55.0 * u(random)) * std::numbers::pi / 180.0;
        const double tanY = std::tan(0.5 * c.fovY), tanX = std::tan(0.5 * c.fovX());
        bool inside = true;
        for (const double sx : {-1.0, 1.0}) {
            for (const double sy : {-1.0, 1.0}) {
                const glm::dvec3 ray = c.forward() + sx * tanX * c.right() + sy * tanY * c.up();
                if (ray.z >= 0.0) {
                    inside = false;
                    continue;
                }
                const double t = (floorM - c.position.z) / ray.z;
                const glm::dvec3 hit = c.position + t * ray;
                const glm::dvec2 s = g.sampleOfWorld(hit.x, hit.y);
                inside = inside && s.x > 0.0 && s.x < lastColumn && s.y > 0.0 && s.y < lastRow;
            }
        }
        if (inside) return c;
    }
    ADD_FAILURE() << "no pose found whose view is all terrain";
    return {};
}

/// Runs frames of `camera` until the session has something to draw: the root is the one
/// tile every view must wait for. Whether it arrived: !session.draws().empty().
inline void waitForTheRoot(runtime::TerrainSession& session, const runtime::Camera& camera) {
    for (int i = 0; i < 5000 && session.draws().empty(); ++i) {
        session.beginFrame(camera);
        runtime::FrameTelemetry t;
        session.endFrame(t);
        session.streamer().waitForReads(std::chrono::milliseconds(100));
    }
}

/// Pixels of `fb` that still hold kHoleColor.
inline std::uint64_t countHolePixels(const gl::Framebuffer& fb) {
    const std::vector<std::uint8_t> rgba = fb.readColorRgba8();
    std::uint64_t count = 0;
    for (std::size_t i = 0; i + 3 < rgba.size(); i += 4) {
        count += rgba[i] == 255 && rgba[i + 1] == 0 && rgba[i + 2] == 255 ? 1 : 0;
    }
    return count;
}

}  // namespace terrain::test
