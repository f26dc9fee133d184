// NativeTiles: the finest tiles of a globe pyramid's native grids (ManifestGlobeSource::native;
// docs/globe.md, "Native leaves") named in the globe's own patch ids, so the streaming, the
// tile cache and the GPU pool hold them as any patch and the pyramid's reader reads them
// (PyramidReader): the finest patch (x, y) of the native grid of source k (its index in
// globe.sources) is PatchId{kNativeLevelBase + k, x, y}, a level no globe layout reaches (its face
// levels end at ManifestGlobe::kLevelOffset + kMaxGlobeFaceLevel).
#pragma once

#include "terrain/pyramid/GlobeLayout.h"
#include "terrain/pyramid/PyramidLayout.h"
#include "terrain/pyramid/PyramidManifest.h"

#include "terrain/base/Result.h"

#include <cstdint>
#include <filesystem>
#include <vector>

namespace terrain::io {

inline constexpr int kNativeLevelBase = 64;
/// Sources a pyramid's native grids may belong to: indices 0 … kMaxNativeGrids − 1 of its
/// globe.sources (more sources may have none).
inline constexpr int kMaxNativeGrids = 64;
static_assert(kNativeLevelBase > ManifestGlobe::kLevelOffset + kMaxGlobeFaceLevel);

inline PatchId nativeTileId(int grid, std::int64_t x, std::int64_t y) {
    return PatchId{kNativeLevelBase + grid, x, y};
}
inline bool isNativeTile(const PatchId& id) {
    return id.level >= kNativeLevelBase && id.level < kNativeLevelBase + kMaxNativeGrids;
}
/// The source whose native grid a native tile is of: its index in the manifest's globe.sources.
inline int nativeGridOf(const PatchId& id) { return id.level - kNativeLevelBase; }

/// A globe pyramid's native grid: its source's index in globe.sources and its planar
/// pyramid's manifest (the grid's georeference and tiles).
struct NativeGridManifest {
    int source = 0;
    PyramidManifest manifest;
};

/// The manifests of the native grids of the globe pyramid at `pyramidDir` (a folder or a URL)
/// whose manifest is `manifest`, in source order; none for a pyramid without any. Errors name
/// the grid's folder: a missing or broken manifest, tiles unlike the globe's (they share its
/// GPU pool), more sources with one than kMaxNativeGrids.
Result<std::vector<NativeGridManifest>> readNativeGridManifests(
    const std::filesystem::path& pyramidDir, const PyramidManifest& manifest);

}  // namespace terrain::io
