// TileResidency: the seam between the LOD and streaming, the handful of calls the LOD makes
// to learn which patches it may draw and to ask for the ones it wants. TileStreamer
// (runtime/streaming) implements it over the I/O thread, the CPU cache and the GPU pool;
// the LOD's tests use FakeTileResidency (tests/support), which makes tiles resident on a
// chosen frame and fails chosen ids on one thread, without GL.
//
// A patch the LOD draws must be resident: its layer holds its heights and block errors.
// "Resident" is the implementation's word for that; the LOD only asks and pins.
#pragma once

#include "terrain/pyramid/BlockHeightRanges.h"
#include "terrain/pyramid/PatchRecord.h"
#include "terrain/pyramid/PyramidLayout.h"

#include <optional>

namespace terrain::runtime {

/// Render thread only (one thread: whichever thread runs the LOD).
class TileResidency {
public:
    virtual ~TileResidency() = default;

    /// The LOD wants `id` this frame. Its summary when resident (which also keeps it
    /// resident through this frame); otherwise null, after making sure it is on its way:
    /// requested with `priority` (higher first; re-prioritised every frame), unless it
    /// failed before.
    virtual const io::PatchInfo* acquire(const io::PatchId& id, float priority) = 0;
    /// The layer of a resident patch (acquire() returned its info this frame, or pinned).
    virtual int layerOf(const io::PatchId& id) const = 0;
    /// `id` failed to load and will not be asked for again: whatever covers it draws in
    /// its place.
    virtual bool hasFailed(const io::PatchId& id) const = 0;
    /// Keeps a resident patch resident until unpin(), whatever later frames want: the LOD
    /// tree pins the patches it holds. `id` must be resident and not pinned.
    virtual void pin(const io::PatchId& id) = 0;
    virtual void unpin(const io::PatchId& id) = 0;
    /// The LOD expects to want `id` soon (it predicts that a patch whose children are on
    /// their way will split again once they come): read it into the CPU cache, not the GPU,
    /// at `priority`, unless it is resident, cached, on its way, failed or known absent. A
    /// patch the pyramid turns out not to store (the sparse globe's, below a patch whose
    /// children are on their way) is no failure: it is known absent from then on. Kept
    /// wanted only while asked for every frame, as acquire()'s requests are. Default:
    /// nothing (tests' residencies).
    virtual void prefetch(const io::PatchId& id, float priority) {
        (void)id;
        (void)priority;
    }
    /// Whether `id` was read ahead and found absent (prefetch): its descendants are absent too.
    virtual bool knownAbsent(const io::PatchId& id) const {
        (void)id;
        return false;
    }
    /// How many patches can be resident at once (the GPU pool's layers).
    virtual int capacity() const = 0;

    /// The summary of `id` if it is resident now, else null; neither requests nor keeps it
    /// (for ground-height queries and invariant checks).
    virtual const io::PatchInfo* residentInfo(const io::PatchId& id) const = 0;
    virtual bool isPinned(const io::PatchId& id) const = 0;
    /// io::sampleRises of `id`'s heights if it is resident now (the steepest rises between
    /// neighbouring samples, which bound the slopes of the flat triangles drawn from it);
    /// nullopt otherwise, and by default (tests' residencies, which know no heights: the LOD
    /// then bounds the triangles' sag alone).
    virtual std::optional<io::SampleRises> residentSampleRises(const io::PatchId& id) const {
        (void)id;
        return std::nullopt;
    }

protected:
    TileResidency() = default;
    TileResidency(const TileResidency&) = default;
    TileResidency& operator=(const TileResidency&) = default;
};

}  // namespace terrain::runtime
