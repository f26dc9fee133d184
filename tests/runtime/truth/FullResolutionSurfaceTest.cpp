// The ground truth of the accuracy measures without a GPU: FullResolutionSurface reads the
// finest level of a tiny pyramid (written sample by sample, so every height is known) and
// evaluates the full-resolution mesh — both diagonals of a cell, the reference renderer's
// own — and measureScreenSpaceError turns a depth image into the projected vertical
// distances to it, checked against an independent ray cast of a plane.
#include "TempFolder.h"
#include "TinyPyramid.h"
#include "terrain/runtime/FullResolutionSurface.h"
#include "terrain/runtime/PlaneTruth.h"
#include "terrain/runtime/ScreenSpaceError.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace terrain::test {
namespace {

struct TinySurface {
    TempFolder folder;
    TinyPyramidOptions options;
    std::filesystem::path path;
};

std::unique_ptr<TinySurface> writeTiny(bool noData = false) {
    auto t = std::make_unique<TinySurface>();
    t->options.width = 37;
    t->options.height = 29;
    t->options.withNoData = noData;
    t->path = t->folder.path() / "tiny.pyramid";
    auto written = writeTinyPyramid(t->path, t->options);
    EXPECT_TRUE(written) << written.error().message;
    return t;
}

/// DEM sample (i, j) clamped into the DEM, as the pyramid stores beyond its edge.
double demHeight(const TinyPyramidOptions& o, std::int64_t i, std::int64_t j) {
    return tinyHeight(o.seed, std::clamp<std::int64_t>(i, 0, o.width - 1),
                      std::clamp<std::int64_t>(j, 0, o.height - 1));
}

TEST(FullResolutionSurface, CellHeightsOfBothDiagonals) {
    // Corners 0 (NW), 10 (NE), 20 (SW), 50 (SE).
    for (const auto f : {runtime::cellHeightNwSe, runtime::cellHeightNeSw}) {
        EXPECT_DOUBLE_EQ(f(0, 10, 20, 50, 0, 0), 0);
        EXPECT_DOUBLE_EQ(f(0, 10, 20, 50, 1, 0), 10);
        EXPECT_DOUBLE_EQ(f(0, 10, 20, 50, 0, 1), 20);
        EXPECT_DOUBLE_EQ(f(0, 10, 20, 50, 1, 1), 50);
        EXPECT_DOUBLE_EQ(f(0, 10, 20, 50, 0.5, 0), 5);  // along the north edge: linear
        EXPECT_DOUBLE_EQ(f(0, 10, 20, 50, 1, 0.5), 30);
    }
    // The centre lies on the diagonal each one draws.
    EXPECT_DOUBLE_EQ(runtime::cellHeightNwSe(0, 10, 20, 50, 0.5, 0.5), 25);
    EXPECT_DOUBLE_EQ(runtime::cellHeightNeSw(0, 10, 20, 50, 0.5, 0.5), 15);
}

TEST(FullResolutionSurface, SamplesAndMeshOfTheFinestLevel) {
    const auto tiny = writeTiny();
    auto opened = runtime::FullResolutionSurface::open(tiny->path);
    ASSERT_TRUE(opened) << opened.error().message;
    runtime::FullResolutionSurface& s = opened.value();
    const runtime::TerrainGeometry& g = s.geometry();
    const std::int64_t lastX = s.layout().levelSamplesX(s.finestLevel()) - 1;
    const std::int64_t lastY = s.layout().levelSamplesY(s.finestLevel()) - 1;
    for (std::int64_t j = 0; j <= lastY; ++j) {
        for (std::int64_t i = 0; i <= lastX; ++i) {
            auto h = s.sample(i, j);
            ASSERT_TRUE(h) << h.error().message;
            ASSERT_EQ(h.value(), demHeight(tiny->options, i, j)) << i << ", " << j;
        }
    }
    const std::int64_t demLastX = tiny->options.width - 1, demLastY = tiny->options.height - 1;
    ASSERT_LT(demLastX, lastX) << "the tiny DEM's last patches overhang it";
    for (std::int64_t j = 0; j < demLastY; j += 3) {
        for (std::int64_t i = 0; i < demLastX; i += 2) {
            const double h00 = demHeight(tiny->options, i, j),
                         h10 = demHeight(tiny->options, i + 1, j);
            const double h01 = demHeight(tiny->options, i, j + 1),
                         h11 = demHeight(tiny->options, i + 1, j + 1);
            const glm::dvec2 at = g.worldOfSample(static_cast<double>(i), static_cast<double>(j));
            auto corner = s.heightAt(at.x, at.y);
            ASSERT_TRUE(corner && corner.value().inside);
            EXPECT_NEAR(corner.value().referenceM, h00, 1e-9);
            EXPECT_NEAR(corner.value().highM - corner.value().lowM, 0.0, 1e-9);
            const glm::dvec2 centre =
                g.worldOfSample(static_cast<double>(i) + 0.5, static_cast<double>(j) + 0.5);
            auto mid = s.heightAt(centre.x, centre.y);
            ASSERT_TRUE(mid && mid.value().inside);
            EXPECT_NEAR(mid.value().referenceM, 0.5 * (h00 + h11),
                        1e-9);  // the reference's diagonal
            EXPECT_NEAR(mid.value().lowM, std::min(0.5 * (h00 + h11), 0.5 * (h10 + h01)), 1e-9);
            EXPECT_NEAR(mid.value().highM, std::max(0.5 * (h00 + h11), 0.5 * (h10 + h01)), 1e-9);
        }
    }
    // Beyond the DEM's extent there is no surface, though the pyramid stores clamped
    // samples there (the last patches overhang the DEM).
    const glm::dvec2 beyond = g.worldOfSample(static_cast<double>(demLastX) + 0.5, 1.0);
    auto outside = s.heightAt(beyond.x, beyond.y);
    ASSERT_TRUE(outside);
    EXPECT_FALSE(outside.value().inside);
    const glm::dvec2 edge = s.clampToDem(beyond.x, beyond.y);
    EXPECT_NEAR(g.sampleOfWorld(edge.x, edge.y).x, static_cast<double>(demLastX), 1e-9);
    const glm::dvec2 lastSample =
        g.worldOfSample(static_cast<double>(demLastX), static_cast<double>(demLastY));
    auto corner = s.heightAt(lastSample.x, lastSample.y);
    ASSERT_TRUE(corner && corner.value().inside);
    EXPECT_NEAR(corner.value().referenceM, demHeight(tiny->options, demLastX, demLastY), 1e-9);
}

TEST(FullResolutionSurface, HeightRangeSpansTheWholeSquareItIsAskedFor) {
    // A square of half-side 3 samples centred on a sample: its corners and sides lie on
    // sample lines, so the mesh's range over it is the range of the 7 × 7 samples. The
    // measure asks for squares of several samples when a pixel spans a hundred (a DEM seen
    // from far); this once stopped at 1 sample and reported 8 px errors that a twentieth
    // of a pixel sideways explained.
    const auto tiny = writeTiny();
    auto opened = runtime::FullResolutionSurface::open(tiny->path);
    ASSERT_TRUE(opened) << opened.error().message;
    runtime::FullResolutionSurface& s = opened.value();
    const runtime::TerrainGeometry& g = s.geometry();
    const std::int64_t ci = 18, cj = 14, r = 3;
    const glm::dvec2 centre = g.worldOfSample(static_cast<double>(ci), static_cast<double>(cj));
    const glm::dvec2 east = g.worldOfSample(static_cast<double>(ci + r), static_cast<double>(cj));
    const glm::dvec2 north = g.worldOfSample(static_cast<double>(ci), static_cast<double>(cj + r));
    const double radiusM = std::abs(east.x - centre.x);
    ASSERT_NEAR(std::abs(north.y - centre.y), radiusM, 1e-9) << "square samples";

    double low = std::numeric_limits<double>::infinity(), high = -low;
    for (std::int64_t j = cj - r; j <= cj + r; ++j) {
        for (std::int64_t i = ci - r; i <= ci + r; ++i) {
            low = std::min(low, demHeight(tiny->options, i, j));
            high = std::max(high, demHeight(tiny->options, i, j));
        }
    }
    auto range = s.heightRange(centre.x, centre.y, radiusM);
    ASSERT_TRUE(range) << range.error().message;
    ASSERT_TRUE(range.value().inside);
    EXPECT_DOUBLE_EQ(range.value().lowM, low);
    EXPECT_DOUBLE_EQ(range.value().highM, high);

    // The data tells the two apart: one sample around the centre is a narrower range.
    auto oneSample = s.heightRange(centre.x, centre.y, radiusM / static_cast<double>(r));
    ASSERT_TRUE(oneSample);
    EXPECT_GT(oneSample.value().highM - oneSample.value().lowM, 0.0);
    EXPECT_LT(oneSample.value().highM - oneSample.value().lowM, high - low);
}

TEST(FullResolutionSurface, KeepsItsPatchesWithinTheBudget) {
    const auto tiny = writeTiny();
    auto whole = runtime::FullResolutionSurface::open(tiny->path);
    ASSERT_TRUE(whole);
    auto first = whole.value().patch({whole.value().finestLevel(), 0, 0});
    ASSERT_TRUE(first);
    const std::size_t onePatch = whole.value().residentBytes();
    ASSERT_GT(onePatch, 0u);
    auto small = runtime::FullResolutionSurface::open(tiny->path, 2 * onePatch);
    ASSERT_TRUE(small);
    const io::PyramidLayout& l = small.value().layout();
    const int finest = l.finestLevel();
    for (int pass = 0; pass < 2; ++pass) {
        for (std::int64_t y = 0; y < l.patchesY(finest); ++y) {
            for (std::int64_t x = 0; x < l.patchesX(finest); ++x) {
                ASSERT_TRUE(small.value().patch({finest, x, y}));
                EXPECT_LE(small.value().residentBytes(), 2 * onePatch);
            }
        }
    }
    // Two passes over more patches than fit: every patch read twice.
    EXPECT_EQ(small.value().patchReads(), 2u * static_cast<std::uint64_t>(l.patchCount(finest)));
    EXPECT_FALSE(runtime::FullResolutionSurface::open(tiny->folder.path() / "missing.pyramid"));
}

TEST(ScreenSpaceError, ProjectionRoundTrip) {
    runtime::Camera c;
    c.viewportWidth = 64;
    c.viewportHeight = 48;
    c.position = {100.0, 200.0, 50.0};
    c.yaw = 0.7;
    c.pitch = -0.4;
    const glm::dmat4 vp = c.relativeViewProjection();
    const glm::dmat4 inverse = glm::inverse(vp);
    for (const double depth : {0.9, 0.01, 1e-5}) {
        const glm::dvec3 rel = runtime::unprojectPixel(inverse, 64, 48, 10, 30, depth);
        const glm::dvec2 px = runtime::projectToPixels(vp, 64, 48, rel);
        EXPECT_NEAR(px.x, 10.5, 1e-6);
        EXPECT_NEAR(px.y, 30.5, 1e-6);
        // depth = near / distance along the view axis (reversed Z, infinite far plane).
        EXPECT_NEAR(glm::dot(rel, c.forward()), c.nearPlane / depth, 1e-6 * c.nearPlane / depth);
    }
    EXPECT_TRUE(std::isnan(runtime::projectToPixels(vp, 64, 48, -10.0 * c.forward()).x));
}

TEST(ScreenSpaceError, MeasuresAPlaneAboveTheMesh) {
    // The "LOD" is the plane z = 150 m, ray-cast exactly; every pixel's error is the
    // projected vertical distance from the plane to the mesh below or above it.
    const auto tiny = writeTiny();
    auto opened = runtime::FullResolutionSurface::open(tiny->path);
    ASSERT_TRUE(opened);
    runtime::FullResolutionSurface& s = opened.value();
    runtime::PlaneTruth exactTruth(s, 0.0);
    runtime::PlaneTruth tolerantTruth(s);
    const runtime::TerrainGeometry& g = s.geometry();
    runtime::Camera c;
    c.viewportWidth = 40;
    c.viewportHeight = 30;
    c.fovY = 0.8;
    // The tiny DEM has no georeference: 1 m between samples, heights within ±130 m.
    c.position = {g.worldAtFraction(0.5, 1.3), 175.0};
    c.lookAt({g.worldAtFraction(0.5, 0.5), 140.0});
    constexpr double kPlaneM = 150.0;
    const glm::dmat4 vp = c.relativeViewProjection();
    const glm::dmat4 inverse = glm::inverse(vp);
    std::vector<float> depth(40 * 30, 0.0f);
    double expectedMax = 0.0;
    std::uint64_t expectedPixels = 0;
    for (int y = 0; y < 30; ++y) {
        for (int x = 0; x < 40; ++x) {
            // The ray through the pixel's centre, from two unprojected points.
            const glm::dvec3 far = runtime::unprojectPixel(inverse, 40, 30, x, y, 1e-3);
            const glm::dvec3 dir = glm::normalize(far);
            if (dir.z >= 0.0) continue;
            const double t = (kPlaneM - c.position.z) / dir.z;
            const glm::dvec3 rel = t * dir;
            const glm::dvec3 world = c.position + rel;
            auto below = s.heightAt(world.x, world.y);
            ASSERT_TRUE(below);
            if (!below.value().inside) continue;
            depth[static_cast<std::size_t>(y * 40 + x)] =
                static_cast<float>(c.nearPlane / glm::dot(rel, c.forward()));
            const double nearest = std::clamp(kPlaneM, below.value().lowM, below.value().highM);
            const glm::dvec2 a = runtime::projectToPixels(vp, 40, 30, rel);
            const glm::dvec2 b =
                runtime::projectToPixels(vp, 40, 30, rel + glm::dvec3(0, 0, nearest - kPlaneM));
            expectedMax = std::max(expectedMax, glm::length(a - b));
            ++expectedPixels;
        }
    }
    ASSERT_GT(expectedPixels, 200u);
    // Measured at exactly each point's x, y, as the expectation is computed.
    auto measured = runtime::measureScreenSpaceError(c, depth, {}, {}, exactTruth, 1.0);
    ASSERT_TRUE(measured) << measured.error().message;
    const runtime::ScreenSpaceErrorStats& e = measured.value();
    // Float depth moves each point along its ray by a relative 1e-7: a tiny difference.
    EXPECT_EQ(e.pixels, expectedPixels);
    // The plane's error field is smooth: adjacent pixels agree to a small fraction.
    EXPECT_NEAR(e.maxSinglePixelPx, expectedMax, 1e-3 * expectedMax + 1e-3);
    EXPECT_LE(e.maxPx, e.maxSinglePixelPx);
    EXPECT_GT(e.maxPx, 0.8 * e.maxSinglePixelPx);
    EXPECT_GT(e.maxPx, 1.0);
    EXPECT_GT(e.pixelsOverThreshold, 0u);
    EXPECT_EQ(e.outsidePixels, 0u);
    EXPECT_EQ(e.nonFinitePixels, 0u);
    EXPECT_LE(e.meanPx, e.maxPx);
    EXPECT_LE(e.p99Px, e.maxPx);
    EXPECT_GE(e.maxFixedDiagonalPx, e.maxPx);
    // A skirtless depth that differs marks skirt pixels, left out of the figures.
    std::vector<float> noSkirts = depth;
    noSkirts[static_cast<std::size_t>(e.worstY * 40 + e.worstX)] = 0.0f;
    auto skirted = runtime::measureScreenSpaceError(c, depth, noSkirts, {}, exactTruth, 1.0);
    ASSERT_TRUE(skirted);
    EXPECT_EQ(skirted.value().skirtPixels, 1u);
    EXPECT_EQ(skirted.value().pixels, expectedPixels - 1);
    // NaN depth is counted, never measured.
    depth[0] = std::numeric_limits<float>::quiet_NaN();
    auto withNan = runtime::measureScreenSpaceError(c, depth, {}, {}, exactTruth, 1.0);
    ASSERT_TRUE(withNan);
    EXPECT_EQ(withNan.value().nonFinitePixels, 1u);
    // The horizontal tolerance only ever lowers a pixel's error, by no more than the
    // surface's slope times a twentieth of a pixel: the plane's error mostly remains.
    depth[0] = 0.0f;
    auto tolerant = runtime::measureScreenSpaceError(c, depth, {}, {}, tolerantTruth, 1.0);
    ASSERT_TRUE(tolerant);
    EXPECT_EQ(tolerant.value().pixels, expectedPixels);
    EXPECT_LE(tolerant.value().maxSinglePixelPx, e.maxSinglePixelPx);
    EXPECT_GT(tolerant.value().maxSinglePixelPx, 0.5 * e.maxSinglePixelPx);
    EXPECT_NEAR(tolerant.value().maxExactPositionPx, e.maxSinglePixelPx, 1e-9);
}

/// Reversed-Z depth of the full-resolution mesh moved `shiftXM` metres east, ray-marched
/// through every pixel's centre (0 where the ray misses it): an LOD drawn exactly, or
/// exactly but a little sideways.
std::vector<float> rayMarchedDepth(const runtime::Camera& c, runtime::FullResolutionSurface& s,
                                   double shiftXM = 0.0) {
    const int w = c.viewportWidth, h = c.viewportHeight;
    const glm::dmat4 inverse = glm::inverse(c.relativeViewProjection());
    std::vector<float> depth(static_cast<std::size_t>(w * h), 0.0f);
    const auto below = [&](const glm::dvec3& p) {
        auto height = s.heightAt(p.x - shiftXM, p.y);
        return height && height.value().inside && p.z < height.value().referenceM;
    };
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const glm::dvec3 dir =
                glm::normalize(runtime::unprojectPixel(inverse, w, h, x, y, 1e-3));
            double lo = 0.0, hi = 0.0;
            for (double t = 0.0; t < 800.0; t += 0.25) {
                if (below(c.position + t * dir)) {
                    hi = t;
                    break;
                }
                lo = t;
            }
            if (hi == 0.0) continue;
            for (int i = 0; i < 60; ++i) {
                const double mid = 0.5 * (lo + hi);
                (below(c.position + mid * dir) ? hi : lo) = mid;
            }
            depth[static_cast<std::size_t>(y * w + x)] =
                static_cast<float>(c.nearPlane / glm::dot(hi * dir, c.forward()));
        }
    }
    return depth;
}

/// A 20 × 16 px camera above the tiny DEM's highest sample, looking north over it.
runtime::Camera cameraAboveTiny(const runtime::TerrainGeometry& g) {
    runtime::Camera c;
    c.viewportWidth = 20;
    c.viewportHeight = 16;
    c.fovY = 0.5;
    c.position = {g.worldAtFraction(0.5, 0.5), 140.0};
    c.lookAt({g.worldAtFraction(0.5, 0.1), 0.0});
    return c;
}

TEST(ScreenSpaceError, ALonePixelDoesNotSetTheMaximum) {
    // The full-resolution mesh itself, ray-marched (an exact "LOD": no error anywhere), with
    // one pixel's depth pushed along its ray (what an edge-on triangle's depth can be): the
    // single-pixel maximum sees it, the maximum two adjacent pixels agree on does not.
    const auto tiny = writeTiny();
    auto opened = runtime::FullResolutionSurface::open(tiny->path);
    ASSERT_TRUE(opened);
    runtime::FullResolutionSurface& s = opened.value();
    runtime::PlaneTruth exactTruth(s, 0.0);
    const runtime::Camera c = cameraAboveTiny(s.geometry());
    std::vector<float> depth = rayMarchedDepth(c, s);
    const std::size_t lone = 4 * 20 + 10;
    ASSERT_GT(depth[lone], 0.0f);
    auto exact = runtime::measureScreenSpaceError(c, depth, {}, {}, exactTruth, 0.1);
    ASSERT_TRUE(exact);
    EXPECT_GT(exact.value().pixels, 80u);
    EXPECT_LT(exact.value().maxSinglePixelPx, 0.01);
    depth[lone] *= 0.8f;  // 25 % further along its ray: well under the surface
    auto spiked = runtime::measureScreenSpaceError(c, depth, {}, {}, exactTruth, 0.1);
    ASSERT_TRUE(spiked);
    EXPECT_GT(spiked.value().maxSinglePixelPx, 0.2);
    EXPECT_LT(spiked.value().maxPx, 0.01);
    EXPECT_EQ(spiked.value().pixelsOverThreshold, 1u);
}

TEST(ScreenSpaceError, ASidewaysSlipOnASteepSlopeIsWithinTheHorizontalTolerance) {
    // The tiny DEM climbs up to 130 m between adjacent samples 1 m apart: a slope of 130.
    // Its mesh drawn exactly but 0.045 px east (what vertex snapping does, an order of
    // magnitude larger) is tenths of a pixel off vertically; measured against the
    // surface within 0.05 px sideways it is exact (docs/accuracy.md, "Steep slopes").
    const auto tiny = writeTiny();
    auto opened = runtime::FullResolutionSurface::open(tiny->path);
    ASSERT_TRUE(opened);
    runtime::FullResolutionSurface& s = opened.value();
    runtime::PlaneTruth exactTruth(s, 0.0);
    runtime::PlaneTruth tolerantTruth(s);
    const runtime::Camera c = cameraAboveTiny(s.geometry());
    // One pixel at the nearest ground the camera sees (depth = near / distance).
    const std::vector<float> unshifted = rayMarchedDepth(c, s);
    const double nearestM =
        c.nearPlane / static_cast<double>(*std::max_element(unshifted.begin(), unshifted.end()));
    const double nearestPixelM = nearestM * 2.0 * std::tan(0.5 * c.fovY) / c.viewportHeight;
    const std::vector<float> depth = rayMarchedDepth(c, s, 0.045 * nearestPixelM);

    auto exact = runtime::measureScreenSpaceError(c, depth, {}, {}, exactTruth, 0.1);
    ASSERT_TRUE(exact);
    EXPECT_GT(exact.value().pixels, 80u);
    EXPECT_GT(exact.value().maxSinglePixelPx, 0.08)
        << "the slip shows at exactly each point's x, y";
    auto tolerant = runtime::measureScreenSpaceError(c, depth, {}, {}, tolerantTruth, 0.1);
    ASSERT_TRUE(tolerant);
    EXPECT_EQ(tolerant.value().pixels, exact.value().pixels);
    EXPECT_LT(tolerant.value().maxSinglePixelPx, 0.01);
    EXPECT_EQ(tolerant.value().pixelsOverThreshold, 0u);
    EXPECT_DOUBLE_EQ(tolerant.value().maxExactPositionPx, exact.value().maxSinglePixelPx);
}

}  // namespace
}  // namespace terrain::test
