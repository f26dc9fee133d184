// RowSpan (io/pyramid/src/RowSpan.h), the integer row extents of the strip errors'
// triangles, takes the same samples as the floating-point crossings it replaced, on every
// triangle with corners in a 9 × 9 grid and offset across a 129-sample patch.
#include "RowSpan.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace terrain::io {
namespace {

struct Point {
    int x, y;
};

// The form interiorDeviation used before RowSpan: crossings in doubles, then ⌈x − 1e-9⌉ and
// ⌊x + 1e-9⌋.
std::pair<int, int> floatingSpan(Point a, Point b, Point c, int y) {
    double xLo = std::numeric_limits<double>::infinity(), xHi = -xLo;
    for (auto [p, q] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}}) {
        if ((y < p.y && y < q.y) || (y > p.y && y > q.y)) continue;
        if (p.y == q.y) {
            xLo = std::min({xLo, double(p.x), double(q.x)});
            xHi = std::max({xHi, double(p.x), double(q.x)});
        } else {
            const double x = p.x + double(y - p.y) * (q.x - p.x) / (q.y - p.y);
            xLo = std::min(xLo, x);
            xHi = std::max(xHi, x);
        }
    }
    return {static_cast<int>(std::ceil(xLo - 1e-9)), static_cast<int>(std::floor(xHi + 1e-9))};
}

std::pair<int, int> integerSpan(Point a, Point b, Point c, int y) {
    const RowSpan span = triangleRowSpan({a.x, a.y}, {b.x, b.y}, {c.x, c.y}, y);
    return {span.first, span.last};
}

TEST(RowSpan, FloorAndCeilingOfQuotients) {
    EXPECT_EQ(floorDiv(7, 2), 3);
    EXPECT_EQ(floorDiv(-7, 2), -4);
    EXPECT_EQ(floorDiv(-8, 2), -4);
    EXPECT_EQ(ceilDiv(7, 2), 4);
    EXPECT_EQ(ceilDiv(-7, 2), -3);
    EXPECT_EQ(ceilDiv(0, 3), 0);
}

TEST(RowSpan, SameSamplesAsTheFloatingPointCrossings) {
    constexpr int kSide = 9;
    long rows = 0, mismatches = 0;
    for (const int offset : {0, 120}) {  // a block at a patch's start and near its end
        for (int a = 0; a < kSide * kSide; ++a)
            for (int b = 0; b < kSide * kSide; ++b)
                for (int c = 0; c < kSide * kSide; ++c) {
                    const Point pa{offset + a % kSide, offset + a / kSide};
                    const Point pb{offset + b % kSide, offset + b / kSide};
                    const Point pc{offset + c % kSide, offset + c / kSide};
                    const long area2 = long(pb.x - pa.x) * (pc.y - pa.y) -
                                       long(pc.x - pa.x) * (pb.y - pa.y);
                    if (area2 == 0) continue;  // interiorDeviation skips them
                    const int yLo = std::min({pa.y, pb.y, pc.y}), yHi = std::max({pa.y, pb.y, pc.y});
                    for (int y = yLo; y <= yHi; ++y, ++rows)
                        if (floatingSpan(pa, pb, pc, y) != integerSpan(pa, pb, pc, y)) ++mismatches;
                }
    }
    EXPECT_GT(rows, 1000000);
    EXPECT_EQ(mismatches, 0);
}

}  // namespace
}  // namespace terrain::io
