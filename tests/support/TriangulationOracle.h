// A brute-force model of the renderer's surface, sharing no code with the error-bound
// implementation: a grid cell is drawn as two triangles along either diagonal (the GPU
// tessellator picks which), so the surface at a point is one of (up to) two heights,
// found here by barycentric interpolation.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <utility>
#include <vector>

namespace terrain::test {

struct Point3 {
    double x, y, z;
};

/// Height of the plane through triangle (p, q, r) at (x, y), if (x, y) lies inside it.
inline bool heightInTriangle(Point3 p, Point3 q, Point3 r, double x, double y, double& z) {
    const double det = (q.y - r.y) * (p.x - r.x) + (r.x - q.x) * (p.y - r.y);
    const double l1 = ((q.y - r.y) * (x - r.x) + (r.x - q.x) * (y - r.y)) / det;
    const double l2 = ((r.y - p.y) * (x - r.x) + (p.x - r.x) * (y - r.y)) / det;
    const double l3 = 1.0 - l1 - l2;
    const double eps = 1e-12;
    if (l1 < -eps || l2 < -eps || l3 < -eps) return false;
    z = l1 * p.z + l2 * q.z + l3 * r.z;
    return true;
}

/// Every height the surface of the cell with corners (cx, cy) … (cx + s, cy + s) can have
/// at (x, y): one per diagonal. `height(i, j)` gives grid heights.
inline std::vector<double> cellSurfaceHeights(const std::function<double(int, int)>& height, int cx,
                                              int cy, int s, double x, double y) {
    auto corner = [&](int i, int j) {
        return Point3{double(cx + i * s), double(cy + j * s), height(cx + i * s, cy + j * s)};
    };
    const Point3 a = corner(0, 0), b = corner(1, 0), c = corner(0, 1), d = corner(1, 1);
    std::vector<double> out;
    double z = 0.0;
    for (auto [t1, t2] : {std::pair{std::array{a, b, d}, std::array{a, c, d}},
                          std::pair{std::array{a, b, c}, std::array{b, c, d}}}) {
        if (heightInTriangle(t1[0], t1[1], t1[2], x, y, z) ||
            heightInTriangle(t2[0], t2[1], t2[2], x, y, z))
            out.push_back(z);
    }
    return out;
}

/// The largest vertical distance between the plane through triangle (p, q, r), whose
/// corners lie on the grid's samples, and the grid's full-resolution surface under it,
/// over every diagonal choice of every cell. Exact: the triangle is clipped against each
/// fine triangle of each cell it may overlap, and both surfaces are planar on each piece,
/// so the distance is largest at a vertex of a piece.
inline double triangleSurfaceDeviation(const std::function<double(int, int)>& height, Point3 p,
                                       Point3 q, Point3 r) {
    using Polygon = std::vector<std::array<double, 2>>;
    // The part of `polygon` on the left of the directed line a → b (Sutherland–Hodgman).
    auto clip = [](const Polygon& polygon, std::array<double, 2> a, std::array<double, 2> b) {
        auto side = [&](const std::array<double, 2>& v) {
            return (b[0] - a[0]) * (v[1] - a[1]) - (b[1] - a[1]) * (v[0] - a[0]);
        };
        Polygon out;
        for (std::size_t i = 0; i < polygon.size(); ++i) {
            const auto& u = polygon[i];
            const auto& v = polygon[(i + 1) % polygon.size()];
            const double su = side(u), sv = side(v);
            if (su >= 0.0) out.push_back(u);
            if ((su >= 0.0) != (sv >= 0.0)) {
                const double t = su / (su - sv);
                out.push_back({u[0] + t * (v[0] - u[0]), u[1] + t * (v[1] - u[1])});
            }
        }
        return out;
    };
    // Counter-clockwise corners, so "left of every edge" is inside.
    auto ccw = [](std::array<Point3, 3> t) {
        const double area =
            (t[1].x - t[0].x) * (t[2].y - t[0].y) - (t[2].x - t[0].x) * (t[1].y - t[0].y);
        if (area < 0.0) std::swap(t[1], t[2]);
        return t;
    };
    auto planeAt = [](const std::array<Point3, 3>& t, double x, double y) {
        const double det =
            (t[1].x - t[0].x) * (t[2].y - t[0].y) - (t[2].x - t[0].x) * (t[1].y - t[0].y);
        const double wb =
            ((x - t[0].x) * (t[2].y - t[0].y) - (t[2].x - t[0].x) * (y - t[0].y)) / det;
        const double wc =
            ((t[1].x - t[0].x) * (y - t[0].y) - (x - t[0].x) * (t[1].y - t[0].y)) / det;
        return t[0].z + wb * (t[1].z - t[0].z) + wc * (t[2].z - t[0].z);
    };
    const std::array<Point3, 3> triangle = ccw({p, q, r});
    const int x0 = int(std::min({p.x, q.x, r.x})), x1 = int(std::max({p.x, q.x, r.x}));
    const int y0 = int(std::min({p.y, q.y, r.y})), y1 = int(std::max({p.y, q.y, r.y}));
    double worst = 0.0;
    for (int cy = y0; cy < y1; ++cy) {
        for (int cx = x0; cx < x1; ++cx) {
            auto corner = [&](int i, int j) {
                return Point3{double(cx + i), double(cy + j), height(cx + i, cy + j)};
            };
            const Point3 a = corner(0, 0), b = corner(1, 0), c = corner(0, 1), d = corner(1, 1);
            for (const auto& fine : {std::array{a, b, d}, std::array{a, c, d}, std::array{a, b, c},
                                     std::array{b, c, d}}) {
                const auto f = ccw(fine);
                Polygon piece = {{triangle[0].x, triangle[0].y},
                                 {triangle[1].x, triangle[1].y},
                                 {triangle[2].x, triangle[2].y}};
                for (int e = 0; e < 3 && !piece.empty(); ++e) {
                    const Point3 &u = f[static_cast<std::size_t>(e)],
                                 &v = f[static_cast<std::size_t>((e + 1) % 3)];
                    piece = clip(piece, {u.x, u.y}, {v.x, v.y});
                }
                for (const auto& vertex : piece)
                    worst = std::max(worst, std::abs(planeAt(f, vertex[0], vertex[1]) -
                                                     planeAt(triangle, vertex[0], vertex[1])));
            }
        }
    }
    return worst;
}

}  // namespace terrain::test
