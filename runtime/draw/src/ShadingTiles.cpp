// ShadingTiles: a patch's samples on its tile's ancestors, by halving.
#include "terrain/runtime/ShadingTiles.h"

#include "terrain/base/Assert.h"
#include "terrain/pyramid/NativeTiles.h"

#include <cstdint>

namespace terrain::runtime {

AncestorTile ancestorTile(const DrawnTile& tile, int k, int patchQuads) {
    TERRAIN_ASSERT(k >= 0 && k <= tile.id.level, "ancestorTile: above the root");
    const std::int64_t mask = (std::int64_t{1} << k) - 1;
    const double scale = 1.0 / static_cast<double>(std::int64_t{1} << k);
    // Tile sample u of `tile` lies on sample ((x mod 2^k) · N + u) / 2^k of the ancestor.
    const auto offset = [&](std::int64_t position, float texelOffset) {
        return static_cast<float>(
            (static_cast<double>((position & mask) * patchQuads) + double(texelOffset)) * scale);
    };
    return {.id = {tile.id.level - k, tile.id.x >> k, tile.id.y >> k},
            .texelOffset = {offset(tile.id.x, tile.texelOffset[0]),
                            offset(tile.id.y, tile.texelOffset[1])},
            .texelStep = static_cast<float>(double(tile.texelStep) * scale)};
}

void shadingTilesOf(const DrawnTile& tile, int patchQuads,
                    const std::function<std::optional<int>(AncestorTile&)>& layerOf,
                    std::span<ShadingTile, kShadingAncestors> out) {
    ShadingTile coarsest{tile.texelOffset[0], tile.texelOffset[1], tile.texelStep,
                         static_cast<float>(tile.layer)};
    // A native tile (a source's own grid) has no tile above it: its id's "parent" names
    // another source's native tile (kNativeLevelBase + k − 1), which the shader would read.
    bool found = tile.layer >= 0 && !io::isNativeTile(tile.id);
    for (int k = 1; k <= kShadingAncestors; ++k) {
        if (found && k <= tile.id.level) {
            AncestorTile ancestor = ancestorTile(tile, k, patchQuads);
            if (const std::optional<int> layer = layerOf(ancestor)) {
                coarsest = {ancestor.texelOffset[0], ancestor.texelOffset[1], ancestor.texelStep,
                            static_cast<float>(*layer)};
            } else {
                found = false;
            }
        }
        out[static_cast<std::size_t>(k - 1)] = coarsest;
    }
}

}  // namespace terrain::runtime
