// The transition strips' checks of a block size: which segments and triangles a strip may
// hold (GL 4.5 §11.2.2.2; PatchErrors.h, transitionErrors) and where each is compared with
// the full-resolution surface, worked out once; then evaluated per block.
#include "StripChecks.h"

#include "RowSpan.h"

#include "terrain/base/Assert.h"
#include "terrain/pyramid/PyramidLayout.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <mutex>

namespace terrain::io::detail {
namespace {

constexpr int kFactors = 17;  // log2 of factors up to 2^16, far beyond GL's 64

constexpr int log2Of(int powerOfTwo) { return std::countr_zero(static_cast<unsigned>(powerOfTwo)); }

}  // namespace

const StripChecks& StripChecks::forBlock(int blockQuads) {
    TERRAIN_ASSERT(blockQuads >= 1 && blockQuads <= PyramidLayout::kMaxBlockQuads &&
                       std::has_single_bit(static_cast<unsigned>(blockQuads)),
                   "a block of 1 to 64 quads, a power of two (PyramidLayout)");
    constexpr auto kSizes = static_cast<std::size_t>(log2Of(PyramidLayout::kMaxBlockQuads) + 1);
    static std::array<std::unique_ptr<StripChecks>, kSizes> shared;
    static std::array<std::once_flag, kSizes> built;
    const auto slot = static_cast<std::size_t>(log2Of(blockQuads));
    std::call_once(built[slot], [&] { shared[slot] = std::make_unique<StripChecks>(blockQuads); });
    return *shared[slot];
}

StripChecks::StripChecks(int blockQuads) : m_blockQuads(blockQuads) {
    // The strips each λ(d) bounds, and every inner factor's strips once.
    std::array<bool, kFactors> added{};
    for (int d = 1; d <= kMaxSimplification; ++d) {
        const int innerFactor = std::max(1, blockQuads >> d);
        // An inner factor of 1 becomes 2 once an edge is finer (GL 4.5 §11.2.2.2); then an
        // edge of factor 1 joins the centre too.
        const int inner = std::max(2, innerFactor);
        const int firstEdgeFactor = innerFactor == 1 ? 1 : 2 * innerFactor;
        if (blockQuads < 2 || firstEdgeFactor > blockQuads) continue;  // no finer edge
        m_levels[static_cast<std::size_t>(d - 1)] = {log2Of(inner), log2Of(firstEdgeFactor)};
        if (added[static_cast<std::size_t>(log2Of(inner))]) continue;
        addStrips(inner);
        added[static_cast<std::size_t>(log2Of(inner))] = true;
    }
    for (Slot& slot : m_slots) {
        for (auto* list : {&slot.segments, &slot.triangles}) {
            std::sort(list->begin(), list->end());
            list->erase(std::unique(list->begin(), list->end()), list->end());
        }
    }
    m_segmentIndex.clear();
    m_triangleIndex.clear();
}

// The strips of inner factor `inner` (≥ 2, a power of two) against edges of every
// power-of-two factor m from 1 (inner 2) or 2·inner up to blockQuads, on the four edges.
// The triangles a driver may make: two consecutive vertices of one side and one of the
// other within one inner spacing of the pair's span (PatchErrors.cpp explains why).
void StripChecks::addStrips(int inner) {
    const int blockQuads = m_blockQuads;
    const int innerSpacing = blockQuads / inner;
    const int innerCount = inner - 1;  // vertices of the inner mesh's side, j = 1..inner−1
    auto withinReach = [&](int along, int from, int to) {
        return along >= from - innerSpacing && along <= to + innerSpacing;
    };
    auto slotFor = [&](int edgeFactor) -> Slot& {
        const int innerLog2 = log2Of(inner), edgeLog2 = log2Of(edgeFactor);
        for (Slot& slot : m_slots)
            if (slot.innerLog2 == innerLog2 && slot.edgeLog2 == edgeLog2) return slot;
        return m_slots.emplace_back(Slot{innerLog2, edgeLog2, {}, {}});
    };
    for (int edge = 0; edge < 4; ++edge) {
        // Edge `edge`'s frame: `along` runs along the edge, `inward` into the block.
        auto at = [&](int along, int inward) -> Point {
            switch (edge) {
                case 0:
                    return {along, inward};
                case 1:
                    return {along, blockQuads - inward};
                case 2:
                    return {inward, along};
                default:
                    return {blockQuads - inward, along};
            }
        };
        auto innerVertex = [&](int j) { return at(j * innerSpacing, innerSpacing); };
        const int firstEdgeFactor = inner == 2 ? 1 : 2 * inner;
        for (int edgeFactor = firstEdgeFactor; edgeFactor <= blockQuads; edgeFactor *= 2) {
            const int edgeSpacing = blockQuads / edgeFactor;
            Slot& slot = slotFor(edgeFactor);
            // Two consecutive edge vertices and an inner vertex. The segments keep the
            // direction they were always measured in (edge to inner vertex, along the
            // edge and the inner side forwards): the same crossings, the same doubles.
            for (int k = 0; k < edgeFactor; ++k) {
                const int from = k * edgeSpacing, to = from + edgeSpacing;
                for (int j = 1; j <= innerCount; ++j) {
                    if (!withinReach(j * innerSpacing, from, to)) continue;
                    slot.segments.push_back(segmentIndex(at(from, 0), at(to, 0)));
                    slot.segments.push_back(segmentIndex(at(from, 0), innerVertex(j)));
                    slot.segments.push_back(segmentIndex(at(to, 0), innerVertex(j)));
                    slot.triangles.push_back(triangleIndex(at(from, 0), at(to, 0), innerVertex(j)));
                }
            }
            // Two consecutive inner vertices and an edge vertex.
            for (int j = 1; j < innerCount; ++j) {
                for (int k = 0; k <= edgeFactor; ++k) {
                    const int along = k * edgeSpacing;
                    if (!withinReach(along, j * innerSpacing, (j + 1) * innerSpacing)) continue;
                    slot.segments.push_back(segmentIndex(innerVertex(j), innerVertex(j + 1)));
                    slot.segments.push_back(segmentIndex(at(along, 0), innerVertex(j)));
                    slot.segments.push_back(segmentIndex(at(along, 0), innerVertex(j + 1)));
                    slot.triangles.push_back(
                        triangleIndex(innerVertex(j), innerVertex(j + 1), at(along, 0)));
                }
            }
        }
    }
}

// The points of segment p → q where |f − L| can be largest, L interpolating the heights at
// p and q linearly and f the full-resolution surface under either diagonal of every cell:
// both are linear between the segment's crossings of grid lines and cell diagonals. Along a
// grid line (an edge of every fine triangulation) the samples are the only such points.
std::uint32_t StripChecks::segmentIndex(Point p, Point q) {
    const auto side = static_cast<std::uint64_t>(m_blockQuads) + 1;
    const std::uint64_t key =
        ((std::uint64_t(p.x) * side + std::uint64_t(p.y)) * side + std::uint64_t(q.x)) * side +
        std::uint64_t(q.y);
    if (auto found = m_segmentIndex.find(key); found != m_segmentIndex.end()) return found->second;
    const auto index = static_cast<std::uint32_t>(m_segments.size());
    m_segmentIndex.emplace(key, index);

    // Every crossing, by kind, as the strips were always checked.
    ChecksByKind crossings;
    const int dx = q.x - p.x, dy = q.y - p.y;
    if (dx == 0 || dy == 0) {
        const int steps = std::abs(dx) + std::abs(dy);
        const int sx = (dx > 0) - (dx < 0), sy = (dy > 0) - (dy < 0);
        for (int k = 1; k < steps; ++k)
            crossings[kSample].push_back(
                {double(k) / steps, 0.0, index, p.x + k * sx, p.y + k * sy});
    } else {
        // Crossings of the lines where c(point) = c(p) + s·dc is an integer; the offset is s
        // times the step of the coordinate the surface is interpolated along.
        auto add = [&](Kind kind, int c0, int dc, int offsetStep) {
            if (dc == 0) return;
            const int step = dc > 0 ? 1 : -1;
            for (int k = c0; k != c0 + dc + step; k += step) {
                const double s = double(k - c0) / dc;
                crossings[kind].push_back({s, s * offsetStep, index, k, 0});
            }
        };
        add(kColumn, p.x, dx, dy);                 // column X = k: y = p.y + s·dy
        add(kRow, p.y, dy, dx);                    // row Y = k: x = p.x + s·dx
        add(kDiagonalAD, p.x - p.y, dx - dy, dx);  // x − y = k
        add(kDiagonalBC, p.x + p.y, dx + dy, dx);  // x + y = k
    }

    // A block away from the grid's last row and column never clamps a cell, so a crossing
    // whose offset is a whole number lies on a sample and evaluates to its height exactly
    // (t = 0), whichever lines cross there; s is the same double for all of them (a
    // correctly rounded quotient of the same rational). Such a crossing is checked once,
    // as the sample, and not at all at p (|h(p) − hp| = 0). About half the checks go.
    ChecksByKind merged;
    std::vector<Check>& samples = merged[kSample];
    samples = crossings[kSample];
    for (int kind = kColumn; kind < kKinds; ++kind) {
        for (const Check& c : crossings[static_cast<std::size_t>(kind)]) {
            if (c.offset != std::trunc(c.offset)) {
                merged[static_cast<std::size_t>(kind)].push_back(c);
                continue;
            }
            const int offset = static_cast<int>(c.offset);
            Point at{};
            switch (kind) {
                case kColumn:
                    at = {c.line, p.y + offset};
                    break;
                case kRow:
                    at = {p.x + offset, c.line};
                    break;
                case kDiagonalAD:
                    at = {p.x + offset, p.x + offset - c.line};
                    break;
                default:
                    at = {p.x + offset, c.line - (p.x + offset)};
                    break;
            }
            if (at.x == p.x && at.y == p.y) continue;
            const auto same = std::find_if(samples.begin(), samples.end(), [&](const Check& s) {
                return s.line == at.x && s.other == at.y;
            });
            if (same == samples.end())
                samples.push_back({c.s, 0.0, index, at.x, at.y});
            else
                TERRAIN_ASSERT(same->s == c.s, "one point, one position along the segment");
        }
    }

    for (int kind = 0; kind < kKinds; ++kind) {
        const auto k = static_cast<std::size_t>(kind);
        m_checks[0][k].insert(m_checks[0][k].end(), crossings[k].begin(), crossings[k].end());
        m_checks[1][k].insert(m_checks[1][k].end(), merged[k].begin(), merged[k].end());
    }
    m_segments.push_back({p, q});
    return index;
}

// The samples inside triangle abc (its boundary included), row by row (RowSpan.h).
std::uint32_t StripChecks::triangleIndex(Point a, Point b, Point c) {
    const auto side = static_cast<std::uint64_t>(m_blockQuads) + 1;
    std::uint64_t key = 0;
    for (Point point : {a, b, c})
        key = (key * side + std::uint64_t(point.x)) * side + std::uint64_t(point.y);
    if (auto found = m_triangleIndex.find(key); found != m_triangleIndex.end())
        return found->second;
    const auto index = static_cast<std::uint32_t>(m_triangles.size());
    m_triangleIndex.emplace(key, index);
    const double area2 = double(b.x - a.x) * (c.y - a.y) - double(c.x - a.x) * (b.y - a.y);
    m_triangles.push_back({a, b, c, area2});
    if (area2 == 0.0) return index;  // a flat triangle covers no area: deviation 0
    const int yLo = std::min({a.y, b.y, c.y}), yHi = std::max({a.y, b.y, c.y});
    for (int y = yLo; y <= yHi; ++y) {
        const RowSpan span = triangleRowSpan({a.x, a.y}, {b.x, b.y}, {c.x, c.y}, y);
        for (int x = span.first; x <= span.last; ++x)
            m_triangleSamples.push_back({index, x, y, x - a.x, y - a.y});
    }
    return index;
}

// Largest |f − L| at each segment's checks. Each point is evaluated as the strips always
// were: its coordinate p + s·d from the block's absolute sample position, the cell it lies
// in from that coordinate (truncation is floor here: coordinates are ≥ 0), clamped to the
// grid's last cell, a diagonal outside the grid skipped (a grid corner, checked as a sample).
void StripChecks::segmentDeviations(const GridView& g, int x0, int y0,
                                    std::vector<double>& worst) const {
    // Blocks on the grid's last row or column take every crossing as it was computed
    // (segmentIndex says why).
    const int form = x0 + m_blockQuads < g.side - 1 && y0 + m_blockQuads < g.side - 1 ? 1 : 0;
    // Each segment's start p (absolute) and the heights L interpolates.
    struct Ends {
        int x, y;
        double start, rise;
    };
    thread_local std::vector<Ends> ends;
    const std::size_t count = m_segments.size();
    ends.resize(count);
    worst.assign(count, 0.0);
    for (std::size_t i = 0; i < count; ++i) {
        const Segment& segment = m_segments[i];
        Ends& e = ends[i];
        e.x = x0 + segment.p.x;
        e.y = y0 + segment.p.y;
        e.start = g.at(e.x, e.y);
        e.rise = g.at(x0 + segment.q.x, y0 + segment.q.y) - e.start;
    }
    const int lastCell = g.side - 2;
    // A kind's checks come segment by segment: each segment's largest is kept in a register
    // until the next begins (a store and load of worst[segment] a check made a chain).
    std::uint32_t current = 0;
    double largest = 0.0;
    auto check = [&](const Check& c, double surface) {
        if (c.segment != current) {
            worst[current] = std::max(worst[current], largest);
            current = c.segment;
            largest = 0.0;
        }
        const Ends& e = ends[current];
        largest = std::max(largest, std::abs(surface - (e.start + c.s * e.rise)));
    };
    const ChecksByKind& checks = m_checks[static_cast<std::size_t>(form)];
    for (const Check& c : checks[kSample]) check(c, g.at(x0 + c.line, y0 + c.other));
    for (const Check& c : checks[kColumn]) {
        const int X = x0 + c.line;
        const double y = ends[c.segment].y + c.offset;
        const int cy = std::min(static_cast<int>(y), lastCell);
        const double h0 = g.at(X, cy);
        check(c, h0 + (y - cy) * (g.at(X, cy + 1) - h0));
    }
    for (const Check& c : checks[kRow]) {
        const int Y = y0 + c.line;
        const double x = ends[c.segment].x + c.offset;
        const int cx = std::min(static_cast<int>(x), lastCell);
        const double h0 = g.at(cx, Y);
        check(c, h0 + (x - cx) * (g.at(cx + 1, Y) - h0));
    }
    // Diagonal a–d of cell (cx, cy) runs from (cx, cy) to (cx + 1, cy + 1): x − y = cx − cy.
    for (const Check& c : checks[kDiagonalAD]) {
        const double x = ends[c.segment].x + c.offset;
        const int cx = std::min(static_cast<int>(x), lastCell);
        const int cy = cx - (c.line + x0 - y0);
        if (cy < 0 || cy > lastCell) continue;
        const double t = x - cx, h0 = g.at(cx, cy);
        check(c, h0 + t * (g.at(cx + 1, cy + 1) - h0));
    }
    // Diagonal b–c of cell (cx, cy) runs from (cx, cy + 1) to (cx + 1, cy): x + y = cx + cy + 1.
    for (const Check& c : checks[kDiagonalBC]) {
        const double x = ends[c.segment].x + c.offset;
        const int cx = std::min(static_cast<int>(x), lastCell);
        const int cy = c.line + x0 + y0 - cx - 1;
        if (cy < 0 || cy > lastCell) continue;
        const double t = x - cx, h0 = g.at(cx, cy + 1);
        check(c, h0 + t * (g.at(cx + 1, cy) - h0));
    }
    if (count > 0) worst[current] = std::max(worst[current], largest);
}

// Largest |f − L| at the samples inside each triangle, L the plane through its corners'
// heights: L = ha + gy·(y − a.y) + gx·(x − a.x), evaluated in that order.
void StripChecks::interiorDeviations(const GridView& g, int x0, int y0,
                                     std::vector<double>& worst) const {
    struct Plane {
        double base, slopeX, slopeY;
    };
    thread_local std::vector<Plane> planes;
    const std::size_t count = m_triangles.size();
    planes.resize(count);
    worst.assign(count, 0.0);
    for (std::size_t i = 0; i < count; ++i) {
        const Triangle& t = m_triangles[i];
        if (t.area2 == 0.0) continue;
        const Point a = t.a, b = t.b, c = t.c;
        const double ha = g.at(x0 + a.x, y0 + a.y), hb = g.at(x0 + b.x, y0 + b.y),
                     hc = g.at(x0 + c.x, y0 + c.y);
        planes[i] = {ha, ((hb - ha) * (c.y - a.y) - (hc - ha) * (b.y - a.y)) / t.area2,
                     ((hc - ha) * (b.x - a.x) - (hb - ha) * (c.x - a.x)) / t.area2};
    }
    // The samples come triangle by triangle: each triangle's largest is kept in a register
    // until the next begins (a store and load of worst[t] a sample made a chain).
    std::uint32_t current = 0;
    double largest = 0.0;
    for (const TriangleSample& sample : m_triangleSamples) {
        const std::uint32_t t = sample.triangle;
        if (t != current) {
            worst[current] = largest;
            current = t;
            largest = 0.0;
        }
        const Plane& p = planes[t];
        const double plane = p.base + p.slopeY * sample.dy + p.slopeX * sample.dx;
        largest = std::max(largest, std::abs(g.at(x0 + sample.x, y0 + sample.y) - plane));
    }
    if (!m_triangleSamples.empty()) worst[current] = largest;
}

BlockErrors StripChecks::errors(const GridView& patch, int x0, int y0) const {
    thread_local std::vector<double> segmentWorst, triangleWorst;
    segmentDeviations(patch, x0, y0, segmentWorst);
    interiorDeviations(patch, x0, y0, triangleWorst);

    // strips[log2 inner][log2 m]: the largest deviation of the strips between edges of
    // factor m and an inner mesh of factor `inner` (≥ 2).
    std::array<std::array<double, kFactors>, kFactors> strips{};
    for (const Slot& slot : m_slots) {
        double worst = 0.0;
        for (std::uint32_t s : slot.segments) worst = std::max(worst, segmentWorst[s]);
        for (std::uint32_t t : slot.triangles) worst = std::max(worst, triangleWorst[t]);
        strips[static_cast<std::size_t>(slot.innerLog2)][static_cast<std::size_t>(slot.edgeLog2)] =
            worst;
    }
    BlockErrors errors{};
    for (std::size_t d = 0; d < m_levels.size(); ++d) {
        const Level& level = m_levels[d];
        if (level.innerLog2 < 0) continue;  // no edge finer than the inner factor: 0
        double worst = 0.0;
        for (int m = level.firstEdgeLog2; (1 << m) <= m_blockQuads; ++m)
            worst = std::max(worst, strips[static_cast<std::size_t>(level.innerLog2)]
                                          [static_cast<std::size_t>(m)]);
        errors[d] = roundUpToFloat(worst);
    }
    return errors;
}

}  // namespace terrain::io::detail
