// StripChecks: where the transition strips' error of a block is measured, worked out once
// per block size (the build's hottest loop: issue 50).
#pragma once

#include "terrain/pyramid/PatchErrors.h"

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace terrain::io::detail {

/// The transition strips of a block of `blockQuads` × `blockQuads` quads, as
/// transitionErrors bounds them (PatchErrors.h): every segment and triangle a strip may
/// hold for every inner factor and finer edge factor, and every point where the
/// full-resolution surface is compared with them, with the two samples it is interpolated
/// between, relative to the block's top-left sample. None of this depends on the block's
/// heights, nor on where it lies beyond whether it touches the grid's last row or column
/// (and then whether it is on the first row), so it is worked out once per block size for
/// each such placement; a block's errors are then its heights read at those points, without
/// a crossing search, a division or a rounding of a coordinate a point. Each point is
/// evaluated with the arithmetic the crossings were always checked with (the same doubles,
/// in the same order, from the block's absolute coordinates), so the bounds are the same to
/// the bit.
class StripChecks {
public:
    /// The checks of a block size, a power of two up to PyramidLayout::kMaxBlockQuads, built
    /// on first use and shared (0.8 MiB and 1 ms at 8 quads, the default; 31 MiB and 93 ms
    /// at 64).
    static const StripChecks& forBlock(int blockQuads);

    explicit StripChecks(int blockQuads);

    /// transitionErrors of the block whose top-left sample is (x0, y0) in `patch`.
    BlockErrors errors(const GridView& patch, int x0, int y0) const;

private:
    struct Point {
        int x, y;
    };

    // One point of a segment p → q where the surfaces are compared. `s` is its position
    // along the segment (0 at p, 1 at q); `offset` is s·dx or s·dy, the distance from p's
    // coordinate of the one the fine surface is interpolated along; `line` names the grid
    // line or diagonal crossed (its x, y, x − y or x + y relative to the block), or is a
    // sample's x (`other` its y).
    struct Check {
        double s;
        double offset;
        std::uint32_t segment;
        int line;
        int other;
    };
    // The kinds of point, each in a list of its own: a block's checks run as a few long
    // loops, not many short ones (a segment has a dozen checks over five kinds).
    enum Kind { kSample, kColumn, kRow, kDiagonalAD, kDiagonalBC, kKinds };
    // Form 0 has every crossing as computed (blocks on the grid's last row or column),
    // form 1 those on a sample merged into one check of it (the other blocks).
    using ChecksByKind = std::array<std::vector<Check>, kKinds>;

    // A check as a block of one placement evaluates it, every kind alike, from the block's
    // heights h (heightIndex): the fine surface is h[low] + t·(h[high] − h[low]), where
    // t = (c + offset) − (c + whole), c being the segment start's absolute coordinate along
    // `axis` (0: x, 1: y) and `whole` the distance from it of the cell's first sample
    // (placeChecks says why that is the crossing code's x − cx to the bit). A sample has
    // offset and whole 0, so t = 0 and the surface is h[low].
    struct PointCheck {
        double s, offset, whole;
        std::uint32_t segment;
        std::uint32_t axis;
        std::uint32_t low, high;
    };
    // Where a block lies, as far as its checks care: inside the grid (form 1), or touching
    // its last column or row (form 0), and then whether on its first row.
    enum Place { kInside = 0, kLastColumn = 1, kLastRow = 2, kFirstRow = 4, kPlaces = 8 };
    struct Placement {
        int side, x0, y0;
    };

    struct Segment {
        Point p, q;
    };
    struct Triangle {
        Point a, b, c;
        double area2;  // twice its signed area; 0: flat, no samples
        std::uint32_t ha, hb, hc;  // the corners' places among the block's heights
    };
    // A sample inside a triangle (its boundary included): its place among the block's
    // heights, and its offset from corner a (whole numbers, as the doubles the plane is
    // evaluated with).
    struct TriangleSample {
        std::uint32_t triangle;
        std::uint32_t height;
        double dx, dy;
    };
    // The segments and triangles whose largest deviation is strips[inner][edge factor].
    struct Slot {
        int innerLog2, edgeLog2;
        std::vector<std::uint32_t> segments, triangles;
    };

    // The strips λ(d + 1) bounds: of inner factor 2^innerLog2 against edges from factor
    // 2^firstEdgeLog2 up to the block's quads; innerLog2 < 0 where no edge can be finer.
    struct Level {
        int innerLog2 = -1, firstEdgeLog2 = 0;
    };

    std::uint32_t segmentIndex(Point p, Point q);
    std::uint32_t triangleIndex(Point a, Point b, Point c);
    void addStrips(int inner);

    // Where (x, y) of the block (−1 to blockQuads + 1: a sample around it included) lies
    // among the heights a block's checks read.
    std::uint32_t heightIndex(int x, int y) const {
        return static_cast<std::uint32_t>((y + 1) * (m_blockQuads + 3) + x + 1);
    }
    Placement placementOf(int place) const;
    std::vector<PointCheck> placeChecks(const ChecksByKind& checks, int place) const;

    // `place`: the Place of the block whose top-left sample is (x0, y0).
    void segmentDeviations(int place, int x0, int y0, const double* heights,
                           std::vector<double>& out) const;
    void interiorDeviations(const double* heights, std::vector<double>& out) const;

    int m_blockQuads;
    std::vector<Segment> m_segments;
    std::array<ChecksByKind, 2> m_checks;                        // [form][kind], while building
    std::array<std::vector<PointCheck>, kPlaces> m_pointChecks;  // [Place]
    std::vector<Triangle> m_triangles;
    std::vector<TriangleSample> m_triangleSamples;
    std::vector<Slot> m_slots;
    std::array<Level, kMaxSimplification> m_levels;
    // While building: each segment's and triangle's index by its corners.
    std::unordered_map<std::uint64_t, std::uint32_t> m_segmentIndex, m_triangleIndex;
};

}  // namespace terrain::io::detail
