// CoarseCellErrors: how far a patch drawn as a coarse grid of cells, every cell one quad at
// tessellation factor 1 (two triangles), may lie from the full-resolution surface.
//
// Why: a tessellation block costs at least two triangles, so a patch of K² blocks costs at
// least 2K² however far it is (512 for 16 × 16 blocks of 8 quads, plus its skirts). A
// distant patch whose blocks are all at factor 1 could be drawn with far fewer; cells of
// 2^k × 2^k blocks are that draw. Every cell of a patch has the same size, so cells meet
// without T-junctions, and skirts hide the seams to neighbouring patches as they do for
// blocks.
//
// The bound is derived from what the tile already holds, without a format change: the
// surface of blocks at factor 1 is the full-resolution surface of the grid of block corners,
// so by the triangle inequality
//     |cell − finest| ≤ |cell − blocks at factor 1| + |blocks at factor 1 − patch| + Err(P)
// where the first term is simplificationError over the block-corner grid with step 2^k and
// the second is at most λ(d₁), d₁ = log2(blockQuads), the blocks' factor-1 error (λ covers
// the plain simplification and its strips). Err(P) is added by the caller, as for λ(d).
#pragma once

#include "terrain/pyramid/PatchErrors.h"

#include <span>
#include <vector>

namespace terrain::io {

/// How many coarse cell sizes a patch of `patchQuads` quads with blocks of `blockQuads` has:
/// cells of 2^k × 2^k blocks for k = 1..count (the largest is the whole patch). 0 when λ has
/// no factor-1 level (blockQuads > 2^kMaxSimplification or blockQuads < 2).
int coarseCellLevels(int patchQuads, int blockQuads);

/// Cells of every size together, Σ_k (blocksPerSide / 2^k)²: the length of coarseCellErrors.
int coarseCellCount(int patchQuads, int blockQuads);

/// Where size k's cells start in coarseCellErrors: sizes in order k = 1.., each row-major.
int coarseCellOffset(int blocksPerSide, int k);

/// For every cell of every size k (coarseCellOffset's order): the largest vertical distance
/// between `patch`'s surface (its N × N samples, apron excluded) and the cell drawn as two
/// triangles with either diagonal, bounded as the file comment says (the block-corner grid's
/// simplificationError plus the largest λ(d₁) of the cell's blocks), rounded up to a float.
/// `blockErrors` is the patch's λ, row-major by block; `cornerScratch` holds
/// (blocksPerSide + 1)² floats (so a render thread need not allocate); `out` has
/// coarseCellCount entries.
void coarseCellErrors(const GridView& patch, int blockQuads,
                      std::span<const BlockErrors> blockErrors, std::span<float> cornerScratch,
                      std::span<float> out);

/// The same, allocating its own scratch and result (tools and tests).
std::vector<float> coarseCellErrors(const GridView& patch, int blockQuads,
                                    std::span<const BlockErrors> blockErrors);

}  // namespace terrain::io
