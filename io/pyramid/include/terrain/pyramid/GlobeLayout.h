// GlobeLayout: where a globe pyramid's patches are in the planar layout that stores them
// (docs/pyramid-format.md, "Globe pyramids"). The six cube faces lie side by side, face f
// at columns f · 2^L·(N − 1) …, in one raster of 6·2^L·(N − 1) + 1 × 2^L·(N − 1) + 1
// samples, so shards, the reader, the I/O thread and the caches address a globe's patches
// with the same PatchId as a planar pyramid's; only the LOD and the draw think in faces.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/globe/GlobePatch.h"
#include "terrain/pyramid/PyramidLayout.h"

namespace terrain::io {

/// The finest face level a globe pyramid may have: a level-28 patch of 128 quads has samples
/// 0.3 mm apart, and the runtime's patch keys hold 28 levels.
inline constexpr int kMaxGlobeFaceLevel = 28;

/// The layout of a globe pyramid with face levels 0 … faceFinestLevel.
Result<PyramidLayout> globeLayout(int faceFinestLevel,
                                  int patchSamples = PyramidLayout::kDefaultPatchSamples,
                                  int blockQuads = PyramidLayout::kDefaultBlockQuads,
                                  int shardPatches = PyramidLayout::kDefaultShardPatches);

/// The layout patch that stores a globe patch.
PatchId layoutPatchOf(const globe::GlobePatchId& id);
/// The globe patch a layout patch stores; `id.level` must be ≥ ManifestGlobe::kLevelOffset.
globe::GlobePatchId globePatchOf(const PatchId& id);

}  // namespace terrain::io
