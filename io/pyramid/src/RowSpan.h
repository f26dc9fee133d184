// RowSpan: the samples of one grid row inside a triangle with integer corners, found with
// integer arithmetic (the transition strips' triangles: StripChecks).
#pragma once

#include <algorithm>
#include <limits>
#include <utility>

namespace terrain::io {

/// Floor and ceiling of num / den for den > 0, exact for any signs.
constexpr int floorDiv(int num, int den) {
    return num >= 0 ? num / den : -((-num + den - 1) / den);
}
constexpr int ceilDiv(int num, int den) { return -floorDiv(-num, den); }

/// The integer x range [first, last] of a row between the points where a triangle's edges
/// meet it. A crossing x0 + along·dx/dy (dy ≠ 0) is a rational whose fraction is 0 or at
/// least 1/|dy|, so first = ⌈min x⌉ and last = ⌊max x⌋ are the samples that the earlier
/// floating-point form ⌈x − 1e-9⌉, ⌊x + 1e-9⌋ took for any |dy| below 10^8 (its division
/// was within 1e-12 of the rational): the same samples checked, the same bound.
/// RowSpanTest compares the two on every small triangle.
struct RowSpan {
    int first = std::numeric_limits<int>::max();
    int last = std::numeric_limits<int>::min();

    /// An edge lying along the row, from x = x0 to x1.
    void addSegment(int x0, int x1) {
        first = std::min({first, x0, x1});
        last = std::max({last, x0, x1});
    }
    /// An edge from (x0, y0) with direction (dx, dy), dy ≠ 0, meeting the row y0 + along.
    void addCrossing(int x0, int along, int dx, int dy) {
        int num = along * dx;
        if (dy < 0) {
            num = -num;
            dy = -dy;
        }
        first = std::min(first, x0 + ceilDiv(num, dy));
        last = std::max(last, x0 + floorDiv(num, dy));
    }
};

/// A sample position of the grid (x right, y down).
struct RowSpanPoint {
    int x, y;
};

/// The samples of row y inside the triangle abc, its boundary included: the span between
/// its edges' crossings of the row (first > last when the row misses the triangle).
inline RowSpan triangleRowSpan(RowSpanPoint a, RowSpanPoint b, RowSpanPoint c, int y) {
    RowSpan span;
    for (auto [p, q] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}}) {
        if ((y < p.y && y < q.y) || (y > p.y && y > q.y)) continue;
        if (p.y == q.y)
            span.addSegment(p.x, q.x);
        else
            span.addCrossing(p.x, y - p.y, q.x - p.x, q.y - p.y);
    }
    return span;
}

}  // namespace terrain::io
