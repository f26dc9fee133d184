// StressPoses: one level read into memory, scanned for the steepest step, the sharpest
// peak, the highest sample and a no-data edge; each becomes a camera on the
// full-resolution surface.
#include "StressPoses.h"

#include "terrain/pyramid/PyramidReader.h"
#include "terrain/runtime/FullResolutionSurface.h"
#include "terrain/runtime/TerrainGeometry.h"

#include <fmt/core.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace terrain::tools {
namespace {

constexpr std::int64_t kMaxScanSide = 2049;

/// One level's samples (invalid where no-data or beyond the DEM), row-major.
struct LevelGrid {
    std::int64_t width = 0, height = 0;
    std::int64_t step = 1;  ///< DEM samples between two of the level's
    std::vector<float> heights;
    std::vector<std::uint8_t> valid;
    bool anyNoData = false;

    std::size_t index(std::int64_t x, std::int64_t y) const {
        return static_cast<std::size_t>(y * width + x);
    }
    bool ok(std::int64_t x, std::int64_t y) const {
        return x >= 0 && y >= 0 && x < width && y < height && valid[index(x, y)] != 0;
    }
    float at(std::int64_t x, std::int64_t y) const { return heights[index(x, y)]; }
};

Result<LevelGrid> readScanLevel(io::PyramidReader& reader) {
    const io::PyramidLayout& layout = reader.layout();
    int level = layout.finestLevel();
    while (level > 0 && (layout.levelSamplesX(level) > kMaxScanSide ||
                         layout.levelSamplesY(level) > kMaxScanSide))
        --level;
    LevelGrid grid;
    grid.step = layout.levelStep(level);
    // The level's samples that lie on the DEM.
    grid.width = (layout.rasterWidth() - 1) / grid.step + 1;
    grid.height = (layout.rasterHeight() - 1) / grid.step + 1;
    grid.heights.assign(static_cast<std::size_t>(grid.width * grid.height), 0.0f);
    grid.valid.assign(grid.heights.size(), 0);
    const int n = layout.patchSamples(), tile = layout.tileSamples(), apron = layout.apronSamples();
    io::PatchRecord record;
    for (std::int64_t py = 0; py < layout.patchesY(level); ++py) {
        for (std::int64_t px = 0; px < layout.patchesX(level); ++px) {
            const io::PatchId id{level, px, py};
            if (auto read = reader.readPatch(id, record); !read) return read.error();
            for (int j = 0; j < n; ++j) {
                const std::int64_t y = layout.patchOriginY(id) + j;
                if (y >= grid.height) break;
                for (int i = 0; i < n; ++i) {
                    const std::int64_t x = layout.patchOriginX(id) + i;
                    if (x >= grid.width) break;
                    const std::size_t t = static_cast<std::size_t>((j + apron) * tile + i + apron);
                    const bool valid = record.valid.empty() || record.valid[t] != 0;
                    grid.heights[grid.index(x, y)] = record.heights[t];
                    grid.valid[grid.index(x, y)] = valid ? 1 : 0;
                    grid.anyNoData = grid.anyNoData || !valid;
                }
            }
        }
    }
    return grid;
}

runtime::Camera baseCamera(int widthPx, int heightPx) {
    runtime::Camera c;
    c.viewportWidth = widthPx;
    c.viewportHeight = heightPx;
    c.fovY = 60.0 * std::numbers::pi / 180.0;
    c.nearPlane = 0.5;
    return c;
}

}  // namespace

Result<std::vector<StressPose>> findStressPoses(const std::filesystem::path& pyramid, int widthPx,
                                                int heightPx) {
    auto reader = io::PyramidReader::open(pyramid);
    if (!reader) return reader.error();
    if (reader.value().manifest().globe)
        return Error{pyramid.string() + ": --stability flies planar pyramids only"};
    auto grid = readScanLevel(reader.value());
    if (!grid) return Error{pyramid.string() + ": " + grid.error().message};
    const LevelGrid& g = grid.value();
    auto opened = runtime::FullResolutionSurface::open(pyramid);
    if (!opened) return opened.error();
    runtime::FullResolutionSurface& surface = opened.value();
    const runtime::TerrainGeometry& geometry = surface.geometry();
    const glm::dvec2 spacing = geometry.sampleSpacing() * static_cast<double>(g.step);
    const double levelSpacing = std::max(spacing.x, spacing.y);

    const auto worldOf = [&](std::int64_t x, std::int64_t y) {
        return geometry.worldOfSample(static_cast<double>(x * g.step),
                                      static_cast<double>(y * g.step));
    };
    const auto pointOf = [&](std::int64_t x, std::int64_t y) {
        return glm::dvec3(worldOf(x, y), g.at(x, y));
    };
    // The highest ground within `radiusM` of x, y (the camera must not stand inside it).
    const auto groundNear = [&](glm::dvec2 xy, double radiusM) -> Result<double> {
        auto range = surface.heightRange(xy.x, xy.y, radiusM);
        if (!range) return range.error();
        return range.value().inside ? range.value().highM : geometry.maxHeight();
    };
    const auto describeSample = [&](std::int64_t x, std::int64_t y) {
        return fmt::format("DEM sample ({}, {})", x * g.step, y * g.step);
    };

    // The scans: steepest step between neighbours, sharpest peak over its ring at distance
    // 2, highest sample, first valid sample next to a no-data one.
    double steepest = -1.0, sharpest = -std::numeric_limits<double>::infinity();
    std::int64_t cliffLow[2] = {0, 0}, cliffHigh[2] = {0, 0}, peak[2] = {-1, -1},
                 highest[2] = {-1, -1}, edge[2] = {-1, -1};
    for (std::int64_t y = 0; y < g.height; ++y) {
        for (std::int64_t x = 0; x < g.width; ++x) {
            if (!g.ok(x, y)) continue;
            if (highest[0] < 0 || g.at(x, y) > g.at(highest[0], highest[1]))
                highest[0] = x, highest[1] = y;
            for (const auto& [dx, dy, m] :
                 {std::tuple{1, 0, spacing.x}, std::tuple{0, 1, spacing.y}}) {
                if (!g.ok(x + dx, y + dy)) {
                    if (g.anyNoData && edge[0] < 0 && x + dx < g.width && y + dy < g.height)
                        edge[0] = x, edge[1] = y;
                    continue;
                }
                const double slope = std::abs(g.at(x + dx, y + dy) - g.at(x, y)) / m;
                if (slope > steepest) {
                    steepest = slope;
                    const bool rising = g.at(x + dx, y + dy) > g.at(x, y);
                    cliffLow[0] = rising ? x : x + dx, cliffLow[1] = rising ? y : y + dy;
                    cliffHigh[0] = rising ? x + dx : x, cliffHigh[1] = rising ? y + dy : y;
                }
            }
            float ringMax = -std::numeric_limits<float>::infinity();
            bool whole = true;
            for (std::int64_t j = -2; j <= 2 && whole; ++j) {
                for (std::int64_t i = -2; i <= 2; ++i) {
                    if (!g.ok(x + i, y + j)) {
                        whole = false;
                        break;
                    }
                    const float h = g.at(x + i, y + j);
                    if (std::max(std::abs(i), std::abs(j)) == 2) ringMax = std::max(ringMax, h);
                }
            }
            if (!whole) continue;
            if (g.at(x, y) - ringMax > sharpest) {
                sharpest = g.at(x, y) - ringMax;
                peak[0] = x, peak[1] = y;
            }
        }
    }

    std::vector<StressPose> poses;
    {
        // The whole DEM from about its size away, south of it and above.
        const glm::dvec2 size = geometry.demSize();
        const double extent = std::max(size.x, size.y);
        const glm::dvec3 target{geometry.worldAtFraction(0.5, 0.5),
                                0.5 * (geometry.minHeight() + geometry.maxHeight())};
        runtime::Camera c = baseCamera(widthPx, heightPx);
        c.position = target + glm::dvec3(0.0, -0.7 * extent, 0.9 * extent);
        c.lookAt(target);
        poses.push_back({"whole-terrain", "the whole DEM from afar", c});
    }
    if (steepest > 0.0) {
        // From the foot, 20 level samples away from the step, 2 m above the ground.
        const glm::dvec3 top = pointOf(cliffHigh[0], cliffHigh[1]);
        const glm::dvec3 foot = pointOf(cliffLow[0], cliffLow[1]);
        glm::dvec2 away = glm::dvec2(foot) - glm::dvec2(top);
        away = glm::length(away) > 0.0 ? glm::normalize(away) : glm::dvec2(0.0, -1.0);
        const glm::dvec2 xy = glm::dvec2(foot) + away * (20.0 * levelSpacing);
        auto ground = groundNear(xy, 2.0 * levelSpacing);
        if (!ground) return ground.error();
        runtime::Camera c = baseCamera(widthPx, heightPx);
        c.position = {xy, ground.value() + 2.0};
        c.lookAt(top);
        poses.push_back({"cliff",
                         fmt::format("the steepest slope ({:.2f} m/m, at {}) from its foot",
                                     steepest, describeSample(cliffLow[0], cliffLow[1])),
                         c});
    }
    if (peak[0] >= 0) {
        // From the south, 30 level samples away, at the peak's height (or just above ground).
        const glm::dvec3 top = pointOf(peak[0], peak[1]);
        const glm::dvec2 xy = glm::dvec2(top) + glm::dvec2(0.0, -30.0 * levelSpacing);
        auto ground = groundNear(xy, 2.0 * levelSpacing);
        if (!ground) return ground.error();
        runtime::Camera c = baseCamera(widthPx, heightPx);
        c.position = {xy, std::max(top.z, ground.value() + 2.0)};
        c.lookAt(top);
        poses.push_back({"peak",
                         fmt::format("the sharpest peak ({:.1f} m above its ring, at {})", sharpest,
                                     describeSample(peak[0], peak[1])),
                         c});
    }
    if (highest[0] >= 0) {
        // A walker's view: 1 m above the ground at the DEM's centre, looking level towards
        // its highest point, so the view runs across the terrain to the horizon.
        const glm::dvec2 xy = geometry.worldAtFraction(0.5, 0.5);
        auto ground = groundNear(xy, 0.5 * levelSpacing);
        if (!ground) return ground.error();
        runtime::Camera c = baseCamera(widthPx, heightPx);
        c.position = {xy, ground.value() + 1.0};
        const glm::dvec2 toward = worldOf(highest[0], highest[1]) - xy;
        c.yaw = glm::length(toward) > 0.0 ? std::atan2(toward.x, toward.y) : 0.0;
        c.pitch = 0.0;
        poses.push_back({"grazing",
                         fmt::format("1 m above the ground at the DEM's centre, looking level "
                                     "towards its highest point ({})",
                                     describeSample(highest[0], highest[1])),
                         c});
    }
    if (edge[0] >= 0) {
        // Down at a no-data edge from 50 level samples south of it and as high.
        const glm::dvec3 at = pointOf(edge[0], edge[1]);
        const double d = 50.0 * levelSpacing;
        runtime::Camera c = baseCamera(widthPx, heightPx);
        c.position = at + glm::dvec3(0.0, -d, d);
        c.lookAt(at);
        poses.push_back(
            {"no-data-edge",
             fmt::format("a no-data edge (at {}) from above", describeSample(edge[0], edge[1])),
             c});
    }
    return poses;
}

}  // namespace terrain::tools
