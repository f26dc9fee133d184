// PatchBoundaryImages: what the patch-boundary measures (BoundaryArtefacts.h,
// BoundaryShading.h) share about their inputs: images of one frame drawn by the LOD and the
// reference, and the LOD's patch ids, all of one size; and whether a pixel shows the
// reference's own surface.
#pragma once

#include "terrain/base/Assert.h"
#include "terrain/runtime/BoundaryArtefacts.h"
#include "terrain/runtime/FrameImages.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>

namespace terrain::runtime::detail {

inline void assertSameFrame(const FrameImages& lod, std::span<const std::uint32_t> patchIds,
                            const FrameImages& reference) {
    const std::size_t pixels = lod.pixels();
    TERRAIN_ASSERT(lod.width == reference.width && lod.height == reference.height &&
                       lod.rgba.size() == 4 * pixels && reference.rgba.size() == 4 * pixels &&
                       lod.depth.size() == pixels && reference.depth.size() == pixels &&
                       patchIds.size() == pixels,
                   "a patch-boundary measure: the images, or the patch ids, differ in size");
}

/// Pixel i of the LOD lies on the reference's surface: depths within
/// BoundaryArtefacts::kSameSurface of each other.
inline bool onReferenceSurface(const FrameImages& lod, const FrameImages& reference,
                               std::size_t i) {
    const double depth = lod.depth[i], referenceDepth = reference.depth[i];
    return std::abs(depth - referenceDepth) <=
           BoundaryArtefacts::kSameSurface * std::max(depth, referenceDepth);
}

}  // namespace terrain::runtime::detail
