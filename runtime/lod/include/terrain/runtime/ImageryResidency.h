// ImageryResidency: the seam between the imagery the draw selects per frame and streaming
// (issue 47), as TileResidency is for the heights. TileStreamer's imagery part
// (runtime/streaming) implements it over the same I/O thread and request queue, a CPU cache
// and a GPU texture array of RGBA8 tiles with a free-list, under their own budgets; tests
// may fake it without GL.
//
// Every frame the selection walks each layer's tiles down from the drawn patches, asking for
// the tiles whose texels match the pixels' footprints and drawing from the finest resident
// ancestor of each until it arrives: never a hole. A tile asked for in a frame stays
// requested; one not asked for in a later frame may be cancelled (the view moved on).
#pragma once

#include "terrain/pyramid/ImageryTile.h"
#include "terrain/pyramid/PyramidLayout.h"

#include <optional>

namespace terrain::runtime {

/// Render thread only.
class ImageryResidency {
public:
    virtual ~ImageryResidency() = default;
    /// Imagery layers of the pyramid (the manifest's, bottom first).
    virtual int imageryLayerCount() const = 0;
    /// The GPU texture-array layer holding tile `id` of imagery layer `layer`, which it also
    /// keeps resident through this frame, or nullopt when it is not resident (not even
    /// requested by this: see want()).
    virtual std::optional<int> gpuLayer(int layer, const io::PatchId& id) = 0;
    /// Tile `id`'s info when it has been read (resident on the GPU or held on the CPU), else
    /// null: which children exist, whether it is opaque. A tile that is known absent
    /// (present = false) has an info too.
    virtual const io::ImageryTileInfo* tileInfo(int layer, const io::PatchId& id) const = 0;
    /// This frame wants tile `id` of `layer`: requested with `priority` (higher first,
    /// re-prioritised every frame; the heights' requests use the same scale of pixels) unless
    /// it is resident, on its way or failed before.
    virtual void want(int layer, const io::PatchId& id, float priority) = 0;
    /// Tile `id` of `layer` failed to load and will not be asked for again: its ancestor
    /// draws in its place for good.
    virtual bool hasFailed(int layer, const io::PatchId& id) const = 0;

protected:
    ImageryResidency() = default;
    ImageryResidency(const ImageryResidency&) = default;
    ImageryResidency& operator=(const ImageryResidency&) = default;
};

}  // namespace terrain::runtime
