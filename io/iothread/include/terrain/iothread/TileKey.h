// TileKey: what one request of the streaming I/O thread reads: patch `id` of the heights, or
// tile `id` of imagery layer `imageryLayer` (issue 47). Heights and imagery share one request
// queue, one priority scale and one thread, so a key names the source as well as the patch.
#pragma once

#include "terrain/pyramid/PatchIdHash.h"
#include "terrain/pyramid/PyramidLayout.h"

#include <cstddef>
#include <cstdint>

namespace terrain::io {

struct TileKey {
    /// imageryLayer of the heights' patches.
    static constexpr int kHeights = -1;

    PatchId id;
    int imageryLayer = kHeights;  ///< kHeights, or the manifest's imagery layer (0 bottom)

    constexpr TileKey() = default;
    /// Implicit from a PatchId alone: the heights' key, so the heights' callers keep passing
    /// patches where a key is asked for.
    // NOLINTNEXTLINE(google-explicit-constructor)
    constexpr TileKey(const PatchId& patch, int layer = kHeights)
        : id(patch), imageryLayer(layer) {}

    constexpr bool isImagery() const { return imageryLayer != kHeights; }
    bool operator==(const TileKey&) const = default;
};

struct TileKeyHash {
    /// PatchIdHash of the patch, the layer mixed in (the heights' keys hash as their patch).
    std::size_t operator()(const TileKey& key) const noexcept {
        const std::size_t patch = PatchIdHash{}(key.id);
        if (!key.isImagery()) return patch;
        return patch ^ static_cast<std::size_t>(PatchIdHash::mix(
                           static_cast<std::uint64_t>(key.imageryLayer + 1) * 0x9e3779b97f4a7c15u));
    }
};

}  // namespace terrain::io
