// Error bounds of the patch quadtree (Yusov & Shevtsov 2011, §4 and §5), as pure
// functions over height grids so the builder, the inspector and the tests share them.
//
// The renderer triangulates every grid cell with one of its two diagonals, and which one
// is up to the GPU's tessellator (the GL spec leaves it to the implementation). Every
// bound here therefore takes the maximum over both diagonals of every cell: it holds
// whatever triangulation the hardware picks.
#pragma once

#include <array>
#include <cstddef>
#include <span>
#include <utility>

namespace terrain::io {

/// A read-only, row-major view of a square grid of heights (metres).
struct GridView {
    const float* data = nullptr;
    int side = 0;               ///< Samples per row and per column.
    std::ptrdiff_t stride = 0;  ///< Elements between the starts of two rows.

    float at(int x, int y) const { return data[static_cast<std::ptrdiff_t>(y) * stride + x]; }
};

/// `value` as a float no smaller than it: a bound stays a bound after the conversion.
float roundUpToFloat(double value);

/// The smallest half-precision value at least `bound` (≥ 0), as a float; +∞ beyond the
/// largest half (65,504 m, more than any relief). How shards store block errors.
float roundUpToHalf(float bound);

/// The largest vertical distance between a grid's full-resolution surface and the same
/// grid simplified to every `step`-th sample, over the square region of `quads` × `quads`
/// quads whose top-left sample is (x0, y0). The difference of two piecewise-linear
/// surfaces is largest at a vertex of their common refinement: a sample, or the centre
/// of a fine cell that a coarse diagonal crosses. All samples and all fine cell centres of
/// the region are checked, for every diagonal choice of fine and coarse cells, so the
/// result bounds the distance at any point, full-resolution samples of finer levels
/// included. Rounded up to the next float so it stays a bound after conversion.
float simplificationError(const GridView& grid, int x0, int y0, int quads, int step);

/// The same over a rectangle of quadsX × quadsY quads (both multiples of `step`): a parent
/// at the edge of a level may have children on one side only.
float simplificationError(const GridView& grid, int x0, int y0, int quadsX, int quadsY, int step);

/// Yusov §4, Err_Int(P): the largest vertical distance between the parent patch's surface
/// and its children's joined surface. `children` is the joined height map of the four
/// children (side 2·(N−1)+1); the parent's samples are its even samples
/// (h^(l−1)_{i,j} ≡ h^(l)_{2i,2j}), so this is simplificationError with step 2.
float interpolationError(const GridView& children);

/// Yusov §5, tessellation-block errors λ(d), d = 1..kMaxSimplification: the deviation of
/// the block's triangulation simplified by 2^d from its full-resolution triangulation
/// (a superset of the paper's "samples not in T(d)": the fine cell centres are added so
/// that Λ(d) = λ(d) + Err(P) bounds the distance to the finest samples, not only to the
/// patch's own), or of the transition strips a block with that inner factor can have,
/// whichever is larger (transitionErrors). 4 levels fit a vec4, as in the paper.
inline constexpr int kMaxSimplification = 4;
using BlockErrors = std::array<float, kMaxSimplification>;

/// For d = 1..4: the largest vertical distance between the full-resolution surface and
/// any triangle of the transition strips of a block whose inner tessellation factor is
/// that of simplification d, blockQuads >> d (at least 1), and whose edges are finer: the
/// strips between each edge, at every finer power-of-two factor, and the inner mesh (GL
/// 4.5 §11.2.2.2; an inner factor of 1 becomes 2, a fan about the block's centre). GL
/// leaves the strips' triangulation to the implementation; every triangle that joins two
/// consecutive vertices of one side to a vertex of the other within one inner spacing of
/// them counts (implementations stitch in step; TransitionStripTest checks the driver).
/// Yusov §5 leaves these triangles out; a block's inner factor is its coarsest edge's, so
/// λ(d) must cover them. 0 where no edge can be finer than the inner factor.
BlockErrors transitionErrors(const GridView& patch, int x0, int y0, int blockQuads);

/// λ(1..4) of the block of `blockQuads` × `blockQuads` quads whose top-left sample is
/// (x0, y0) in `patch`: the larger of simplificationError and transitionErrors per level.
/// A simplification coarser than the block (2^d > blockQuads) keeps only the block corners.
BlockErrors blockErrors(const GridView& patch, int x0, int y0, int blockQuads);

/// λ(d) for every block of a patch, row-major by block (blocksPerSide² entries), where
/// blocksPerSide = (patch.side − 1) / blockQuads. `out` must have that many entries.
void patchBlockErrors(const GridView& patch, int blockQuads, std::span<BlockErrors> out);

/// The two heights a grid cell's surface can have at local (u, v) ∈ [0, 1]² (u east, v
/// south), one per diagonal: a–d first, b–c second (corners a north-west, b north-east,
/// c south-west, d south-east).
std::pair<double, double> cellSurfaceHeights(double a, double b, double c, double d, double u,
                                             double v);

}  // namespace terrain::io
