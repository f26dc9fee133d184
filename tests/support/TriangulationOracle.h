// A brute-force model of the renderer's surface, sharing no code with the error-bound
// implementation: a grid cell is drawn as two triangles along either diagonal (the GPU
// tessellator picks which), so the surface at a point is one of (up to) two heights,
// found here by barycentric interpolation.
#pragma once

#include <array>
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

}  // namespace terrain::test
