// SkirtDepth: the CPU's share of the skirts' depth (Yusov & Shevtsov 2011, §5, after
// Ulrich's vertical skirts). Along a shared edge patch A's drawn surface is within Λ_A of
// the full-resolution surface and its neighbour B's within Λ_B, so the crack between them
// is at most Λ_A + Λ_B. The shader knows A's own Λ_A = Λ_ec(d) of the edge; this supplies
// a bound on any neighbour's Λ_B: the largest Err(P) + max λ(d) among the drawn patches.
#pragma once

#include "terrain/cache/GpuTilePool.h"
#include "terrain/runtime/PatchDraw.h"

#include <span>

namespace terrain::runtime {

/// Sets every draw's skirtDepthM to max over `draws` of (errorM + the patch's largest block
/// error λ(d)): a data patch's from its tile (GpuTilePool::maxBlockErrorM; it must be
/// resident, TERRAIN_ASSERT), a bare or virtual one's from its draw. Every drawn patch's
/// Λ(d) for every block and d is at most that. Allocates nothing. Render thread only.
void assignSkirtDepths(std::span<PatchDraw> draws, const cache::GpuTilePool& pool);

}  // namespace terrain::runtime
