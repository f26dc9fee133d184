#include "terrain/pyramid/GlobeLayout.h"

#include "terrain/base/Assert.h"
#include "terrain/pyramid/PyramidManifest.h"

#include <fmt/format.h>

namespace terrain::io {

namespace {
constexpr int kOffset = ManifestGlobe::kLevelOffset;
}  // namespace

Result<PyramidLayout> globeLayout(int faceFinestLevel, int patchSamples, int blockQuads,
                                  int shardPatches) {
    if (faceFinestLevel < 0 || faceFinestLevel > kMaxGlobeFaceLevel)
        return Error{fmt::format("globe face level {} is outside 0 … {}", faceFinestLevel,
                                 kMaxGlobeFaceLevel)};
    const std::int64_t faceSamples =
        (std::int64_t{1} << faceFinestLevel) * std::int64_t{patchSamples - 1};
    Result<PyramidLayout> layout =
        PyramidLayout::create(globe::kCubeFaces * faceSamples + 1, faceSamples + 1, patchSamples,
                              blockQuads, shardPatches);
    if (!layout) return layout;
    // 6·2^L patches wide needs L + 3 levels above the finest (2^(L+2) < 6·2^L ≤ 2^(L+3)).
    TERRAIN_ASSERT(layout.value().finestLevel() == faceFinestLevel + kOffset);
    return layout;
}

PatchId layoutPatchOf(const globe::GlobePatchId& id) {
    return {id.level + kOffset, id.face * globe::patchesPerFaceSide(id.level) + id.x, id.y};
}

globe::GlobePatchId globePatchOf(const PatchId& id) {
    TERRAIN_ASSERT(id.level >= kOffset, "layout levels above the faces hold no globe patch");
    const int level = id.level - kOffset;
    const std::int64_t n = globe::patchesPerFaceSide(level);
    return {static_cast<int>(id.x / n), level, id.x % n, id.y};
}

}  // namespace terrain::io
