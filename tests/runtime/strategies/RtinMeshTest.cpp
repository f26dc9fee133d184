// runtime::RtinMesh on rough synthetic rasters (CPU only): the refined mesh is conforming
// (every interior edge shared by exactly two triangles, so no T-junction and no crack), it
// covers the DEM exactly, every DEM sample lies within its triangle's saturated error, which
// projects to at most τ, the saturations nest down the bintree, a smaller τ never drops a
// triangle's split, and a raster too large for the memory limit is refused with the figures.
#include "terrain/runtime/EdgeTessellation.h"
#include "terrain/runtime/RtinMesh.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <utility>
#include <vector>

namespace terrain::test {
namespace {

using runtime::RtinMesh;
using runtime::RtinTriangle;

std::vector<float> roughHeights(int width, int height, std::uint64_t seed) {
    std::mt19937_64 random(seed);
    std::uniform_real_distribution<float> noise(-4.0f, 4.0f);
    std::vector<float> h(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const double v = 300.0 * std::sin(x * 0.09) * std::cos(y * 0.07) +
                             80.0 * std::sin(x * 0.4 + y * 0.3);
            // A cliff one sample wide down the middle.
            const double cliff = x > width / 2 ? 250.0 : 0.0;
            h[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
              static_cast<std::size_t>(x)] = static_cast<float>(v + cliff) + noise(random);
        }
    }
    return h;
}

runtime::Camera cameraAt(glm::dvec3 position, double yawDeg, double pitchDeg) {
    runtime::Camera c;
    c.position = position;
    c.yaw = yawDeg * std::numbers::pi / 180.0;
    c.pitch = pitchDeg * std::numbers::pi / 180.0;
    c.viewportWidth = 320;
    c.viewportHeight = 240;
    return c;
}

std::int64_t twiceArea(const RtinMesh& mesh, const RtinTriangle& t) {
    const glm::ivec2 a = mesh.sampleOf(t.a), b = mesh.sampleOf(t.b), c = mesh.sampleOf(t.c);
    return std::llabs(static_cast<std::int64_t>(b.x - a.x) * (c.y - a.y) -
                      static_cast<std::int64_t>(b.y - a.y) * (c.x - a.x));
}

/// Every edge of an uncull'd mesh of a (2^k + 1)² raster: shared by two triangles inside,
/// by one on the raster's border; the triangles cover the raster once.
void expectConforming(const RtinMesh& mesh, const std::vector<RtinTriangle>& triangles) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
    std::int64_t area = 0;
    for (const RtinTriangle& t : triangles) {
        area += twiceArea(mesh, t);
        for (const auto& [p, q] : {std::pair{t.a, t.b}, std::pair{t.b, t.c}, std::pair{t.c, t.a}})
            ++edges[{std::min(p, q), std::max(p, q)}];
    }
    const int n = mesh.gridQuads();
    EXPECT_EQ(area, 2LL * n * n) << "the triangles must cover the raster exactly once";
    for (const auto& [edge, count] : edges) {
        const glm::ivec2 p = mesh.sampleOf(edge.first), q = mesh.sampleOf(edge.second);
        const bool border =
            (p.x == q.x && (p.x == 0 || p.x == n)) || (p.y == q.y && (p.y == 0 || p.y == n));
        EXPECT_EQ(count, border ? 1 : 2)
            << "edge (" << p.x << "," << p.y << ")–(" << q.x << "," << q.y << "): a T-junction";
    }
}

TEST(RtinMeshTest, RefinedMeshIsConformingAndCoversTheRasterOnce) {
    constexpr int kSize = 129;
    auto mesh = RtinMesh::build(kSize, kSize, roughHeights(kSize, kSize, 1), {10.0, 10.0});
    ASSERT_TRUE(mesh) << mesh.error().message;
    std::vector<RtinTriangle> triangles;
    for (const double tau : {0.5, 2.0, 8.0}) {
        for (const runtime::Camera& c : {cameraAt({200.0, -300.0, 600.0}, 30.0, -20.0),
                                         cameraAt({640.0, -640.0, 3000.0}, 0.0, -89.0),
                                         cameraAt({-500.0, 200.0, 80.0}, 120.0, 0.0)}) {
            const runtime::RtinSelectStats stats =
                mesh.value().select(c, {0.0, 0.0}, tau, false, triangles);
            EXPECT_EQ(stats.triangles, triangles.size());
            EXPECT_GT(triangles.size(), 2u) << "a rough raster is refined";
            expectConforming(mesh.value(), triangles);
        }
    }
}

TEST(RtinMeshTest, EverySampleLiesWithinItsTrianglesErrorWhichProjectsWithinTau) {
    constexpr int kSize = 65;
    const glm::dvec2 spacing{5.0, 5.0};
    auto mesh = RtinMesh::build(kSize, kSize, roughHeights(kSize, kSize, 2), spacing);
    ASSERT_TRUE(mesh) << mesh.error().message;
    const RtinMesh& m = mesh.value();
    const runtime::Camera camera = cameraAt({100.0, -40.0, 500.0}, 20.0, -35.0);
    constexpr double kTau = 1.0;
    std::vector<RtinTriangle> triangles;
    m.select(camera, {0.0, 0.0}, kTau, false, triangles);
    const glm::dmat4 viewProjection = camera.relativeViewProjection();
    int checked = 0;
    for (const RtinTriangle& t : triangles) {
        const glm::ivec2 a = m.sampleOf(t.a), b = m.sampleOf(t.b), c = m.sampleOf(t.c);
        if (std::abs(a.x - c.x) + std::abs(a.y - c.y) <= 1) continue;  // three samples: exact
        const glm::ivec2 mid = (a + b) / 2;
        const double e = m.errorOf(mid.x, mid.y);
        const double r = m.radiusOf(mid.x, mid.y);
        // Every sample in the triangle within e of its plane.
        const double area =
            static_cast<double>((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x));
        for (int y = std::min({a.y, b.y, c.y}); y <= std::max({a.y, b.y, c.y}); ++y) {
            for (int x = std::min({a.x, b.x, c.x}); x <= std::max({a.x, b.x, c.x}); ++x) {
                const double wa = ((b.x - x) * (c.y - y) - (b.y - y) * (c.x - x)) / area;
                const double wb = ((c.x - x) * (a.y - y) - (c.y - y) * (a.x - x)) / area;
                const double wc = 1.0 - wa - wb;
                if (wa < -1e-12 || wb < -1e-12 || wc < -1e-12) continue;
                const double plane = wa * m.heightAt(a.x, a.y) + wb * m.heightAt(b.x, b.y) +
                                     wc * m.heightAt(c.x, c.y);
                EXPECT_LE(std::abs(m.heightAt(x, y) - plane), e + 1e-3)
                    << "sample " << x << "," << y;
                // The sphere about the midpoint holds the sample.
                const glm::dvec3 pm =
                    m.positionOf(static_cast<std::uint32_t>(mid.y * (m.gridQuads() + 1) + mid.x));
                const glm::dvec3 ps{x * spacing.x, -y * spacing.y, m.heightAt(x, y)};
                EXPECT_LE(glm::distance(pm, ps), r + 1e-3);
                ++checked;
            }
        }
        // The split test this triangle passed: e projects within τ.
        const glm::dvec3 fromCamera =
            m.positionOf(static_cast<std::uint32_t>(mid.y * (m.gridQuads() + 1) + mid.x)) -
            camera.position;
        const runtime::Aabb cube{.min = fromCamera - glm::dvec3(r),
                                 .max = fromCamera + glm::dvec3(r)};
        EXPECT_LE(e * runtime::verticalErrorPxPerM(
                          viewProjection, {camera.viewportWidth, camera.viewportHeight}, cube),
                  kTau);
    }
    EXPECT_GT(checked, kSize * kSize / 2);
}

TEST(RtinMeshTest, SaturatedErrorsAndSpheresNestDownTheBintree) {
    constexpr int kSize = 33;
    auto mesh = RtinMesh::build(kSize, kSize, roughHeights(kSize, kSize, 3), {1.0, 1.0});
    ASSERT_TRUE(mesh) << mesh.error().message;
    const RtinMesh& m = mesh.value();
    struct Tri {
        glm::ivec2 a, b, c;
    };
    int pairs = 0;
    const auto check = [&](const auto& self, const Tri& t) -> void {
        if (std::abs(t.a.x - t.c.x) + std::abs(t.a.y - t.c.y) <= 1) return;
        const glm::ivec2 mid = (t.a + t.b) / 2;
        const Tri children[2] = {{t.c, t.a, mid}, {t.b, t.c, mid}};
        for (const Tri& child : children) {
            if (std::abs(child.a.x - child.c.x) + std::abs(child.a.y - child.c.y) > 1) {
                const glm::ivec2 cm = (child.a + child.b) / 2;
                EXPECT_GE(m.errorOf(mid.x, mid.y), m.errorOf(cm.x, cm.y));
                const glm::dvec3 d{
                    static_cast<double>(mid.x - cm.x), static_cast<double>(cm.y - mid.y),
                    static_cast<double>(m.heightAt(mid.x, mid.y)) - m.heightAt(cm.x, cm.y)};
                EXPECT_GE(m.radiusOf(mid.x, mid.y) + 1e-4, glm::length(d) + m.radiusOf(cm.x, cm.y));
                ++pairs;
            }
            self(self, child);
        }
    };
    const int n = m.gridQuads();
    check(check, Tri{{0, 0}, {n, n}, {n, 0}});
    check(check, Tri{{n, n}, {0, 0}, {0, n}});
    EXPECT_GT(pairs, 1000);
}

TEST(RtinMeshTest, ASmallerThresholdNeverDrawsFewerTriangles) {
    constexpr int kSize = 100;  // padded to 129²: the padding draws nothing
    auto mesh = RtinMesh::build(kSize, 70, roughHeights(kSize, 70, 4), {30.0, 30.0});
    ASSERT_TRUE(mesh) << mesh.error().message;
    EXPECT_EQ(mesh.value().gridQuads(), 128);
    const runtime::Camera camera = cameraAt({1500.0, -1000.0, 900.0}, 200.0, -25.0);
    std::vector<RtinTriangle> triangles;
    std::size_t previous = 0;
    for (const double tau : {16.0, 8.0, 4.0, 2.0, 1.0, 0.5}) {
        mesh.value().select(camera, {0.0, 0.0}, tau, true, triangles);
        EXPECT_GE(triangles.size(), previous) << "τ = " << tau;
        previous = triangles.size();
        for (const RtinTriangle& t : triangles) {
            const glm::ivec2 a = mesh.value().sampleOf(t.a), b = mesh.value().sampleOf(t.b),
                             c = mesh.value().sampleOf(t.c);
            EXPECT_TRUE(std::min({a.x, b.x, c.x}) <= kSize - 1 && std::min({a.y, b.y, c.y}) <= 69)
                << "a triangle wholly in the padding";
        }
    }
    EXPECT_GT(previous, 200u);
}

TEST(RtinMeshTest, ARasterBeyondTheMemoryLimitIsRefusedWithItsFigures) {
    auto mesh = RtinMesh::build(300, 200, std::vector<float>(300 * 200, 1.0f), {1.0, 1.0}, 1 << 20);
    ASSERT_FALSE(mesh);
    EXPECT_NE(mesh.error().message.find("300 × 200"), std::string::npos) << mesh.error().message;
    EXPECT_NE(mesh.error().message.find("MiB"), std::string::npos) << mesh.error().message;
}

}  // namespace
}  // namespace terrain::test
