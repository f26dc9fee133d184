// GlobePatchBuild: what the whole globe build (GlobePyramidBuilder.cpp) and the region build
// (GlobeShardTiling.cpp) do alike to a patch of the cube-sphere: its key, the patches around it
// that may exist, the summary and λ(d) of its finished tile, and writing a shard of them.
#pragma once

#include "GeographicGrid.h"
#include "terrain/base/Result.h"
#include "terrain/globe/GlobePatch.h"
#include "terrain/pyramid/PatchRecord.h"
#include "terrain/pyramid/PyramidLayout.h"
#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/pyramid/ShardWriter.h"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <unordered_set>
#include <vector>

namespace terrain::io::detail {

/// A patch of one level, as a hash key: face, x and y (each < 2^29 up to face level 28).
using PatchKey = std::uint64_t;
inline PatchKey keyOf(int face, std::int64_t x, std::int64_t y) {
    return (std::uint64_t(face) << 58) | (std::uint64_t(y) << 29) | std::uint64_t(x);
}
inline globe::GlobePatchId idOf(PatchKey key, int level) {
    return {static_cast<int>(key >> 58), level, static_cast<std::int64_t>(key & ((1u << 29) - 1)),
            static_cast<std::int64_t>((key >> 29) & ((1u << 29) - 1))};
}
/// The patch of a face coordinate among n per face side.
inline std::int64_t patchIndex(double coordinate, std::int64_t n) {
    const auto i = static_cast<std::int64_t>(coordinate * double(n));
    return i < 0 ? 0 : i >= n ? n - 1 : i;
}

/// Adds `key`'s edge neighbours, and theirs (which covers the diagonal ones, across cube
/// corners too): the patches a source sample in `key` can make exist (a patch can overlap the
/// extent's outer half pixel without holding a sample centre).
void addPatchesAround(PatchKey key, int level, std::unordered_set<PatchKey>& out);

/// Calls `visit` with each of the patch's three siblings (the other children of its parent;
/// none at face level 0). Every present patch's siblings are present too, so a parent is
/// never drawn in part by a child and in part by its own coarser tile.
template <typename Visit> void forEachSibling(PatchKey key, int level, Visit&& visit) {
    if (level == 0) return;
    const globe::GlobePatchId id = idOf(key, level);
    const std::int64_t x0 = id.x & ~std::int64_t{1}, y0 = id.y & ~std::int64_t{1};
    for (int c = 0; c < 4; ++c) {
        const PatchKey sibling = keyOf(id.face, x0 + (c & 1), y0 + (c >> 1));
        if (sibling != key) visit(sibling);
    }
}

/// Completes a globe patch whose tile heights (rounded, in a lossy build) are final: its
/// PatchInfo (Err(P) = `error`, the children present, the drawn samples' summary; a lossy
/// build's quantError from δ_l and the largest rounding `quantized`) and its block errors.
void finishGlobePatch(const PyramidLayout& layout, int faceLevel, double error,
                      std::uint8_t presentChildren,
                      const std::optional<ManifestQuantization>& quantization, double quantized,
                      PatchRecord& record);

/// δ_l of a face level.
double globeHalfStep(const ManifestQuantization& quantization, const PyramidLayout& layout,
                     int faceLevel);

/// Writes one shard of a face level's patches (all of them in `shard`) into `folder`, coding
/// and compressing them on up to `threads` threads.
Status writeGlobeShard(const std::filesystem::path& folder, const PyramidLayout& layout,
                       const ShardId& shard, const std::vector<const PatchRecord*>& records,
                       const ShardWriterOptions& options,
                       const std::optional<ManifestQuantization>& quantization, unsigned threads);

/// The manifest's record of a source on `grid`: its extent, clamped to the poles (a grid whose
/// first or last row is centred on a pole reaches half a pixel beyond it), −180 … 180 when it
/// wraps around the Earth.
ManifestGlobeSource globeSourceOf(const GeographicGrid& grid, std::string input);

/// The manifest's fields every globe build fills alike: the layout, every source's extent
/// (`sources`, finest first) and the extent "go to the data" goes to (the finest's), the first
/// source's georeference, vertical units and no-data value, every source's inputs, the build
/// tool. Statistics, levels and bounds are the builder's.
PyramidManifest globeManifest(const PyramidLayout& layout, int faceFinestLevel,
                              std::vector<ManifestGlobeSource> sources,
                              std::span<DemReader* const> readers);

}  // namespace terrain::io::detail
