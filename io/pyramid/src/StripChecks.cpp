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

constexpr int log2Of(int powerOfTwo) { return std::countr_zero(static_cast<unsigned>(powerOfTwo)); }

// The power-of-two factors (and block sizes) up to GL's 64 (PyramidLayout::kMaxBlockQuads).
constexpr int kFactors = log2Of(PyramidLayout::kMaxBlockQuads) + 1;

// `list` ordered by each item's rank among those of its owner (a segment or a triangle),
// keeping the order within a rank: the first point of every owner, then the second, and so
// on, so that consecutive points have different owners.
template <typename Item, typename Owner>
void interleave(std::vector<Item>& list, Owner owner) {
    std::vector<std::uint32_t> rank(list.size()), seen, firstOfRank;
    for (std::size_t i = 0; i < list.size(); ++i) {
        const std::uint32_t o = owner(list[i]);
        if (seen.size() <= o) seen.resize(o + 1, 0);
        rank[i] = seen[o]++;
        if (firstOfRank.size() <= rank[i] + 1) firstOfRank.resize(rank[i] + 2, 0);
        ++firstOfRank[rank[i] + 1];
    }
    for (std::size_t r = 1; r < firstOfRank.size(); ++r) firstOfRank[r] += firstOfRank[r - 1];
    std::vector<Item> ordered(list.size());
    for (std::size_t i = 0; i < list.size(); ++i) ordered[firstOfRank[rank[i]]++] = list[i];
    list = std::move(ordered);
}

}  // namespace

const StripChecks& StripChecks::forBlock(int blockQuads) {
    TERRAIN_ASSERT(blockQuads >= 1 && blockQuads <= PyramidLayout::kMaxBlockQuads &&
                       std::has_single_bit(static_cast<unsigned>(blockQuads)),
                   "a block of 1 to 64 quads, a power of two (PyramidLayout)");
    static std::array<std::unique_ptr<StripChecks>, kFactors> shared;
    static std::array<std::once_flag, kFactors> built;
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
    // Where every check reads, for a block inside the grid and for each way a block can
    // touch the grid's last row or column.
    m_pointChecks[kInside] = placeChecks(m_checks[1], kInside);
    for (int place : {+kLastColumn, +kLastRow, kLastColumn | kLastRow, kLastColumn | kFirstRow,
                      kLastColumn | kLastRow | kFirstRow})
        m_pointChecks[static_cast<std::size_t>(place)] = placeChecks(m_checks[0], place);
    m_checks = {};
    // Each list ordered by a point's rank within its segment or triangle first: consecutive
    // points then belong to different ones, so a block's loops raise one segment's or
    // triangle's largest after another without waiting on the last (segmentDeviations).
    for (std::vector<PointCheck>& checks : m_pointChecks)
        interleave(checks, [](const PointCheck& c) { return c.segment; });
    interleave(m_triangleSamples, [](const TriangleSample& t) { return t.triangle; });
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
    m_triangles.push_back(
        {a, b, c, area2, heightIndex(a.x, a.y), heightIndex(b.x, b.y), heightIndex(c.x, c.y)});
    if (area2 == 0.0) return index;  // a flat triangle covers no area: deviation 0
    const int yLo = std::min({a.y, b.y, c.y}), yHi = std::max({a.y, b.y, c.y});
    for (int y = yLo; y <= yHi; ++y) {
        const RowSpan span = triangleRowSpan({a.x, a.y}, {b.x, b.y}, {c.x, c.y}, y);
        for (int x = span.first; x <= span.last; ++x)
            m_triangleSamples.push_back(
                {index, heightIndex(x, y), double(x - a.x), double(y - a.y)});
    }
    return index;
}

// The grid a block of `place` is drawn in for placeChecks: three blocks a side (one where
// the block is both the first and the last row), the block where `place` says.
StripChecks::Placement StripChecks::placementOf(int place) const {
    const bool lastColumn = place & kLastColumn, lastRow = place & kLastRow,
               firstRow = place & kFirstRow;
    const int blocks = firstRow && lastRow ? 1 : 3, q = m_blockQuads;
    return {blocks * q + 1, lastColumn ? (blocks - 1) * q : q,
            lastRow    ? (blocks - 1) * q
            : firstRow ? 0
                       : q};
}

// `checks` as PointChecks for blocks of `place`: for each, the two samples the crossing
// code has always read and the cell it interpolates in, found as that code finds them (the
// cell from the point's coordinate, truncated, clamped to the grid's last cell; a diagonal
// outside the grid skipped) for a block of `place`. What the code does depends on the block's
// position only through `place`: whether the block is on the grid's last column, last row,
// first row (a diagonal's cell can lie one row above the block, and skipped there only on
// the first row), as every sample it reads lies within one of the block (checked below).
//
// The cell is worked out from the offset instead of the coordinate: (int)(c + offset) is
// c + ⌊offset⌋ for every int c ≥ 0 with c + offset ≥ 0, as an offset off the integers is
// further from them than c + offset's rounding (at most 2^-22 below 2^31), and one on them
// is exact. So t = (c + offset) − (c + whole), whole the cell's distance from c, is the
// x − cx the crossing code computes, to the bit, wherever the block lies.
std::vector<StripChecks::PointCheck> StripChecks::placeChecks(const ChecksByKind& checks,
                                                              int place) const {
    constexpr double kMargin = 1e-6;
    const Placement at = placementOf(place);
    const int x0 = at.x0, y0 = at.y0, lastCell = at.side - 2;
    std::vector<PointCheck> placed;
    for (int kind = 0; kind < kKinds; ++kind) {
        for (const Check& c : checks[static_cast<std::size_t>(kind)]) {
            const Point p = m_segments[c.segment].p;
            if (kind == kSample) {
                const std::uint32_t sample = heightIndex(c.line, c.other);
                placed.push_back({c.s, 0.0, 0.0, c.segment, 0, sample, sample});
                continue;
            }
            const double whole = std::floor(c.offset);
            const double fraction = c.offset - whole;
            TERRAIN_ASSERT(fraction == 0.0 || (fraction > kMargin && fraction < 1.0 - kMargin),
                           "a crossing's offset is on an integer or clear of one");
            // As segmentDeviations always computed it, in absolute coordinates.
            const int along = (kind == kColumn ? y0 + p.y : x0 + p.x) + static_cast<int>(whole);
            const int cell = std::min(along, lastCell);
            Point low{}, high{};  // absolute
            switch (kind) {
                case kColumn:
                    low = {x0 + c.line, cell}, high = {x0 + c.line, cell + 1};
                    break;
                case kRow:
                    low = {cell, y0 + c.line}, high = {cell + 1, y0 + c.line};
                    break;
                case kDiagonalAD: {  // cell (cx, cy): x − y = cx − cy
                    const int cy = cell - (c.line + x0 - y0);
                    if (cy < 0 || cy > lastCell) continue;
                    low = {cell, cy}, high = {cell + 1, cy + 1};
                    break;
                }
                default: {  // kDiagonalBC, cell (cx, cy): x + y = cx + cy + 1
                    const int cy = c.line + x0 + y0 - cell - 1;
                    if (cy < 0 || cy > lastCell) continue;
                    low = {cell, cy + 1}, high = {cell + 1, cy};
                    break;
                }
            }
            for (Point corner : {low, high})
                TERRAIN_ASSERT(corner.x - x0 >= -1 && corner.x - x0 <= m_blockQuads + 1 &&
                                   corner.y - y0 >= -1 && corner.y - y0 <= m_blockQuads + 1,
                               "a strip's crossing reads within one sample of its block");
            const int start = kind == kColumn ? y0 + p.y : x0 + p.x;
            placed.push_back({c.s, c.offset, double(cell - start), c.segment,
                              kind == kColumn ? 1U : 0U, heightIndex(low.x - x0, low.y - y0),
                              heightIndex(high.x - x0, high.y - y0)});
        }
    }
    return placed;
}

// Largest |f − L| at each segment's checks, L interpolating the heights at the segment's
// ends. Consecutive checks belong to different segments (the constructor orders them so):
// each raises its segment's largest without waiting on the last, and the largest of values
// ≥ 0 (NaN passed over) is the same in any order.
void StripChecks::segmentDeviations(int place, int x0, int y0, const double* heights,
                                    std::vector<double>& worst) const {
    // Each segment's start p (absolute, as the doubles the crossings were computed from)
    // and the heights L interpolates.
    struct Ends {
        std::array<double, 2> at;
        double start, rise;
    };
    thread_local std::vector<Ends> ends;
    const std::size_t count = m_segments.size();
    ends.resize(count);
    worst.assign(count, 0.0);
    for (std::size_t i = 0; i < count; ++i) {
        const Segment& segment = m_segments[i];
        const double start = heights[heightIndex(segment.p.x, segment.p.y)];
        ends[i] = {{double(x0 + segment.p.x), double(y0 + segment.p.y)},
                   start,
                   heights[heightIndex(segment.q.x, segment.q.y)] - start};
    }
    // Plain pointers: the stores to worst[] do not move them.
    const Ends* const segmentEnds = ends.data();
    double* const largest = worst.data();
    for (const PointCheck& c : m_pointChecks[static_cast<std::size_t>(place)]) {
        const Ends& e = segmentEnds[c.segment];
        const double at = e.at[c.axis];
        const double t = (at + c.offset) - (at + c.whole), h0 = heights[c.low];
        const double surface = h0 + t * (heights[c.high] - h0);
        double& w = largest[c.segment];
        w = std::max(w, std::abs(surface - (e.start + c.s * e.rise)));
    }
}

// Largest |f − L| at the samples inside each triangle, L the plane through its corners'
// heights: L = ha + gy·(y − a.y) + gx·(x − a.x), evaluated in that order.
void StripChecks::interiorDeviations(const double* heights, std::vector<double>& worst) const {
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
        const double ha = heights[t.ha], hb = heights[t.hb], hc = heights[t.hc];
        planes[i] = {ha, ((hb - ha) * (c.y - a.y) - (hc - ha) * (b.y - a.y)) / t.area2,
                     ((hc - ha) * (b.x - a.x) - (hb - ha) * (c.x - a.x)) / t.area2};
    }
    // Consecutive samples belong to different triangles (the constructor orders them so).
    const Plane* const trianglePlanes = planes.data();
    double* const largest = worst.data();
    for (const TriangleSample& sample : m_triangleSamples) {
        const Plane& p = trianglePlanes[sample.triangle];
        const double plane = p.base + p.slopeY * sample.dy + p.slopeX * sample.dx;
        double& w = largest[sample.triangle];
        w = std::max(w, std::abs(heights[sample.height] - plane));
    }
}

BlockErrors StripChecks::errors(const GridView& patch, int x0, int y0) const {
    // The block's heights and the samples around it, as the doubles every check computes
    // with, row by row (heightIndex); those beyond the grid are never read (nor set).
    thread_local std::vector<double> heights, segmentWorst, triangleWorst;
    const int side = m_blockQuads + 3;
    heights.resize(static_cast<std::size_t>(side) * static_cast<std::size_t>(side));
    for (int y = std::max(-1, -y0); y <= std::min(m_blockQuads + 1, patch.side - 1 - y0); ++y)
        for (int x = std::max(-1, -x0); x <= std::min(m_blockQuads + 1, patch.side - 1 - x0); ++x)
            heights[heightIndex(x, y)] = patch.at(x0 + x, y0 + y);
    const int lastStart = patch.side - 1 - m_blockQuads;
    int place = kInside;
    if (x0 == lastStart || y0 == lastStart)
        place = (x0 == lastStart ? kLastColumn : 0) | (y0 == lastStart ? kLastRow : 0) |
                (y0 == 0 ? kFirstRow : 0);
    segmentDeviations(place, x0, y0, heights.data(), segmentWorst);
    interiorDeviations(heights.data(), triangleWorst);

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
