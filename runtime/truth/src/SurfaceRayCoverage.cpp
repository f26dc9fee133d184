// SurfaceRayCoverage: the ray is walked over the sample grid cell by cell (Amanatides & Woo's
// grid traversal) in sample coordinates, where the grid is regular; x, y of the world map
// to samples affinely, so the ray stays a ray and its hits stay hits.
#include "terrain/runtime/SurfaceRayCoverage.h"

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace terrain::runtime {

namespace {

// Möller–Trumbore, in double: whether the ray meets the triangle at t > 0 (edges included).
bool rayMeetsTriangle(const glm::dvec3& o, const glm::dvec3& d, const glm::dvec3& a,
                      const glm::dvec3& b, const glm::dvec3& c) {
    const glm::dvec3 e1 = b - a, e2 = c - a;
    const glm::dvec3 p = glm::cross(d, e2);
    const double det = glm::dot(e1, p);
    if (det == 0.0) return false;
    const double inv = 1.0 / det;
    const glm::dvec3 s = o - a;
    const double u = glm::dot(s, p) * inv;
    if (u < 0.0 || u > 1.0) return false;
    const glm::dvec3 q = glm::cross(s, e1);
    const double v = glm::dot(d, q) * inv;
    if (v < 0.0 || u + v > 1.0) return false;
    return glm::dot(e2, q) * inv > 0.0;
}

}  // namespace

Result<bool> everyTriangulationCovers(FullResolutionSurface& surface, const glm::dvec3& origin,
                                      const glm::dvec3& direction, double lowerPerMetre) {
    const TerrainGeometry& g = surface.geometry();
    const io::PyramidLayout& l = surface.layout();
    // The ray in sample space: (column, row, height in metres).
    const glm::dvec2 s0 = g.sampleOfWorld(origin.x, origin.y);
    const glm::dvec2 s1 = g.sampleOfWorld(origin.x + direction.x, origin.y + direction.y);
    const glm::dvec3 o{s0, origin.z};
    const glm::dvec3 d{s1 - s0, direction.z};
    const auto lastColumn = static_cast<double>(l.rasterWidth() - 1);
    const auto lastRow = static_cast<double>(l.rasterHeight() - 1);

    // Where the ray is over the DEM's extent: t in [enter, leave] (slabs).
    double enter = 0.0, leave = std::numeric_limits<double>::infinity();
    for (int axis = 0; axis < 2; ++axis) {
        const double last = axis == 0 ? lastColumn : lastRow;
        if (d[axis] == 0.0) {
            if (o[axis] < 0.0 || o[axis] > last) return false;
            continue;
        }
        double a = (0.0 - o[axis]) / d[axis], b = (last - o[axis]) / d[axis];
        if (a > b) std::swap(a, b);
        enter = std::max(enter, a);
        leave = std::min(leave, b);
    }
    if (!(enter <= leave)) return false;

    const auto cellOf = [](double v, double last) {
        return static_cast<std::int64_t>(std::clamp(std::floor(v), 0.0, last - 1.0));
    };
    const glm::dvec3 start = o + enter * d;
    std::int64_t i = cellOf(start.x, lastColumn), j = cellOf(start.y, lastRow);
    const std::int64_t stepI = d.x > 0.0 ? 1 : -1, stepJ = d.y > 0.0 ? 1 : -1;
    const auto nextCrossing = [&](double from, std::int64_t cell, std::int64_t step, double dir) {
        if (dir == 0.0) return std::numeric_limits<double>::infinity();
        const double boundary = static_cast<double>(step > 0 ? cell + 1 : cell);
        return (boundary - from) / dir;
    };
    double tx = enter + nextCrossing(start.x, i, stepI, d.x);
    double ty = enter + nextCrossing(start.y, j, stepJ, d.y);
    const double dtx = d.x == 0.0 ? std::numeric_limits<double>::infinity() : 1.0 / std::abs(d.x);
    const double dty = d.y == 0.0 ? std::numeric_limits<double>::infinity() : 1.0 / std::abs(d.y);
    const std::int64_t lastI = static_cast<std::int64_t>(lastColumn) - 1;
    const std::int64_t lastJ = static_cast<std::int64_t>(lastRow) - 1;
    while (true) {
        std::array<glm::dvec3, 4> corner;  // (i, j), (i + 1, j), (i, j + 1), (i + 1, j + 1)
        for (int k = 0; k < 4; ++k) {
            const std::int64_t ci = i + (k & 1), cj = j + (k >> 1);
            auto h = surface.sample(ci, cj);
            if (!h) return h.error();
            double height = static_cast<double>(h.value());
            if (lowerPerMetre > 0.0) {
                const glm::dvec3 world{
                    g.worldOfSample(static_cast<double>(ci), static_cast<double>(cj)), height};
                height -= lowerPerMetre * glm::length(world - origin);
            }
            corner[static_cast<std::size_t>(k)] = {static_cast<double>(ci), static_cast<double>(cj),
                                                   height};
        }
        const auto& [c00, c10, c01, c11] = corner;
        const bool alongMain =
            rayMeetsTriangle(o, d, c00, c10, c11) || rayMeetsTriangle(o, d, c00, c11, c01);
        const bool alongOther =
            rayMeetsTriangle(o, d, c00, c10, c01) || rayMeetsTriangle(o, d, c10, c11, c01);
        if (alongMain && alongOther) return true;
        // The next cell the ray enters, until it leaves the extent.
        if (tx < ty) {
            if (tx > leave) break;
            i += stepI;
            tx += dtx;
        } else {
            if (ty > leave) break;
            j += stepJ;
            ty += dty;
        }
        if (i < 0 || j < 0 || i > lastI || j > lastJ) break;
    }
    return false;
}

}  // namespace terrain::runtime
