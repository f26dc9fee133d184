// FullResolutionSurface: finest-level patches in an LRU, and the full-resolution mesh
// evaluated in double from their float samples.
#include "terrain/runtime/FullResolutionSurface.h"

#include <glm/common.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace terrain::runtime {

double cellHeightNwSe(double h00, double h10, double h01, double h11, double fx, double fy) {
    // Triangles (NW, NE, SE) above the diagonal fx = fy and (NW, SW, SE) below it.
    if (fx >= fy) return h00 + fx * (h10 - h00) + fy * (h11 - h10);
    return h00 + fy * (h01 - h00) + fx * (h11 - h01);
}

double cellHeightNeSw(double h00, double h10, double h01, double h11, double fx, double fy) {
    // Triangles (NW, NE, SW) where fx + fy ≤ 1 and (NE, SW, SE) beyond.
    if (fx + fy <= 1.0) return h00 + fx * (h10 - h00) + fy * (h01 - h00);
    return h11 + (1.0 - fx) * (h01 - h11) + (1.0 - fy) * (h10 - h11);
}

FullResolutionSurface::FullResolutionSurface(io::PyramidReader reader, std::size_t budgetBytes)
    : m_reader(std::move(reader)),
      m_geometry(std::make_unique<TerrainGeometry>(m_reader.manifest())),
      m_budgetBytes(budgetBytes) {}

Result<FullResolutionSurface> FullResolutionSurface::open(const std::filesystem::path& pyramid,
                                                          std::size_t budgetBytes) {
    auto reader = io::PyramidReader::open(pyramid);
    if (!reader) return reader.error();
    return FullResolutionSurface(std::move(reader).value(), budgetBytes);
}

Result<const io::PatchRecord*> FullResolutionSurface::patch(const io::PatchId& id) {
    TERRAIN_ASSERT(id.level >= 0 && id.level <= finestLevel(), "FullResolutionSurface: no such level");
    if (const auto it = m_index.find(id); it != m_index.end()) {
        m_lru.splice(m_lru.begin(), m_lru, it->second);
        return &it->second->record;
    }
    // Evict before reading, but never the last entry standing: one patch always fits.
    Entry entry;
    entry.id = id;
    if (Status read = m_reader.readPatch(id, entry.record); !read) return read.error();
    ++m_patchReads;
    entry.bytes = entry.record.heights.size() * sizeof(float) + entry.record.valid.size() +
                  entry.record.blockErrors.size() * sizeof(io::BlockErrors);
    while (!m_lru.empty() && m_residentBytes + entry.bytes > m_budgetBytes) {
        m_residentBytes -= m_lru.back().bytes;
        m_index.erase(m_lru.back().id);
        m_lru.pop_back();
    }
    m_residentBytes += entry.bytes;
    m_lru.push_front(std::move(entry));
    m_index.emplace(id, m_lru.begin());
    return &m_lru.front().record;
}

Result<io::PatchInfo> FullResolutionSurface::info(const io::PatchId& id) {
    if (const auto it = m_infos.find(id); it != m_infos.end()) return it->second;
    auto read = m_reader.patchInfo(id);
    if (!read) return read.error();
    m_infos.emplace(id, read.value());
    return read.value();
}

Result<float> FullResolutionSurface::sample(std::int64_t i, std::int64_t j) {
    const io::PyramidLayout& l = layout();
    const int finest = finestLevel();
    const std::int64_t quads = l.patchQuads();
    i = std::clamp<std::int64_t>(i, 0, l.levelSamplesX(finest) - 1);
    j = std::clamp<std::int64_t>(j, 0, l.levelSamplesY(finest) - 1);
    const std::int64_t px = std::min(i / quads, l.patchesX(finest) - 1);
    const std::int64_t py = std::min(j / quads, l.patchesY(finest) - 1);
    auto record = patch({finest, px, py});
    if (!record) return record.error();
    const auto tile = static_cast<std::int64_t>(l.tileSamples());
    const std::int64_t texel = (j - py * quads + 1) * tile + (i - px * quads + 1);
    return record.value()->heights[static_cast<std::size_t>(texel)];
}

glm::dvec2 FullResolutionSurface::clampToDem(double x, double y) const {
    const io::PyramidLayout& l = layout();
    const glm::dvec2 s = m_geometry->sampleOfWorld(x, y);
    const auto lastX = static_cast<double>(l.rasterWidth() - 1);
    const auto lastY = static_cast<double>(l.rasterHeight() - 1);
    return m_geometry->worldOfSample(std::clamp(s.x, 0.0, lastX), std::clamp(s.y, 0.0, lastY));
}

Result<SurfaceHeight> FullResolutionSurface::heightAt(double x, double y) {
    const io::PyramidLayout& l = layout();
    const glm::dvec2 s = m_geometry->sampleOfWorld(x, y);
    // The DEM's extent; the padded raster beyond it holds clamped copies, not data.
    const auto lastX = static_cast<double>(l.rasterWidth() - 1);
    const auto lastY = static_cast<double>(l.rasterHeight() - 1);
    // Points the GPU puts exactly on the outer edge may land a rounding error beyond it.
    constexpr double kEdgeSlackSamples = 1e-6;
    if (!(s.x >= -kEdgeSlackSamples && s.x <= lastX + kEdgeSlackSamples &&
          s.y >= -kEdgeSlackSamples && s.y <= lastY + kEdgeSlackSamples)) {
        return SurfaceHeight{};
    }
    return heightAtSample(s);
}

Result<SurfaceHeight> FullResolutionSurface::heightAtSample(const glm::dvec2& s) {
    const io::PyramidLayout& l = layout();
    const int finest = finestLevel();
    const auto lastX = static_cast<double>(l.rasterWidth() - 1);
    const auto lastY = static_cast<double>(l.rasterHeight() - 1);
    const double cx = std::clamp(std::floor(s.x), 0.0, lastX - 1.0);
    const double cy = std::clamp(std::floor(s.y), 0.0, lastY - 1.0);
    const double fx = std::clamp(s.x - cx, 0.0, 1.0);
    const double fy = std::clamp(s.y - cy, 0.0, 1.0);
    const auto ci = static_cast<std::int64_t>(cx);
    const auto cj = static_cast<std::int64_t>(cy);
    // The cell's four samples lie in one patch: its north-west sample's patch, whose
    // N = Q + 1 samples a side reach one sample beyond.
    const std::int64_t quads = l.patchQuads();
    const std::int64_t px = ci / quads, py = cj / quads;
    auto record = patch({finest, px, py});
    if (!record) return record.error();
    const std::vector<float>& h = record.value()->heights;
    const auto tile = static_cast<std::size_t>(l.tileSamples());
    const auto at = [&](std::int64_t i, std::int64_t j) {
        const auto col = static_cast<std::size_t>(i - px * quads + 1);  // + 1: the apron
        const auto row = static_cast<std::size_t>(j - py * quads + 1);
        return static_cast<double>(h[row * tile + col]);
    };
    const double h00 = at(ci, cj), h10 = at(ci + 1, cj), h01 = at(ci, cj + 1),
                 h11 = at(ci + 1, cj + 1);
    const double a = cellHeightNwSe(h00, h10, h01, h11, fx, fy);
    const double b = cellHeightNeSw(h00, h10, h01, h11, fx, fy);
    return SurfaceHeight{
        .inside = true, .referenceM = a, .lowM = std::min(a, b), .highM = std::max(a, b)};
}

Result<HeightRange> FullResolutionSurface::heightRange(double x, double y, double radiusM) {
    const io::PyramidLayout& l = layout();
    const glm::dvec2 s = m_geometry->sampleOfWorld(x, y);
    const glm::dvec2 r = glm::abs(m_geometry->sampleOfWorld(x + radiusM, y + radiusM) - s);
    const double rx = std::min(r.x, kMaxRangeRadiusSamples);
    const double ry = std::min(r.y, kMaxRangeRadiusSamples);
    const auto lastX = static_cast<double>(l.rasterWidth() - 1);
    const auto lastY = static_cast<double>(l.rasterHeight() - 1);
    const double x0 = std::max(s.x - rx, 0.0), x1 = std::min(s.x + rx, lastX);
    const double y0 = std::max(s.y - ry, 0.0), y1 = std::min(s.y + ry, lastY);
    if (!(x0 <= x1 && y0 <= y1)) return HeightRange{};
    HeightRange range{.inside = true,
                      .lowM = std::numeric_limits<double>::infinity(),
                      .highM = -std::numeric_limits<double>::infinity()};
    const auto add = [&](double sx, double sy) -> Status {
        auto h = heightAtSample({sx, sy});
        if (!h) return h.error();
        range.lowM = std::min(range.lowM, h.value().lowM);
        range.highM = std::max(range.highM, h.value().highM);
        return {};
    };
    // Either triangulation is linear between the lines x = i, y = j, x − y = k (the
    // north-west–south-east diagonals) and x + y = k (the others), integer in samples. The
    // extremes of a piecewise-linear surface over a rectangle lie on the vertices of that
    // arrangement within it: the samples inside, the corners, and where the lines cross the
    // rectangle's sides.
    for (const double sx : {x0, x1}) {
        for (const double sy : {y0, y1}) {
            if (Status st = add(sx, sy); !st) return st.error();
        }
    }
    for (double j = std::ceil(y0); j <= y1; ++j) {
        for (double i = std::ceil(x0); i <= x1; ++i) {
            if (Status st = add(i, j); !st) return st.error();
        }
    }
    // Along a side where one coordinate is `fixed`, the other crosses a line of the
    // arrangement at k, k + fixed and k − fixed for integer k.
    const auto side = [&](double fixed, double from, double to, bool fixedIsY) -> Status {
        for (const double shift : {0.0, fixed, -fixed}) {
            for (double k = std::ceil(from - shift); k + shift <= to; ++k) {
                const double along = std::clamp(k + shift, from, to);
                if (Status st = fixedIsY ? add(along, fixed) : add(fixed, along); !st) return st;
            }
        }
        return {};
    };
    for (const double sy : {y0, y1}) {
        if (Status st = side(sy, x0, x1, true); !st) return st.error();
    }
    for (const double sx : {x0, x1}) {
        if (Status st = side(sx, y0, y1, false); !st) return st.error();
    }
    return range;
}

}  // namespace terrain::runtime
