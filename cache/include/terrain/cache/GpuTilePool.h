// GpuTilePool: the resident tiles on the GPU, one layer per patch in three texture arrays
// (heights R32F, tessellation-block errors RGBA32F, the blocks' height ranges RG32F),
// uploaded through a persistent-mapped pixel-buffer ring within a per-frame byte budget.
// Yusov & Shevtsov 2011, §5: texture arrays, a list of unused subresources, one draw call.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/cache/LayerFreeList.h"
#include "terrain/cache/LayerLru.h"
#include "terrain/gl/Buffer.h"
#include "terrain/gl/Fence.h"
#include "terrain/gl/Texture.h"
#include "terrain/pyramid/BlockHeightRanges.h"
#include "terrain/pyramid/PatchIdHash.h"
#include "terrain/pyramid/PatchRecord.h"
#include "terrain/pyramid/PyramidLayout.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

namespace terrain::cache {

struct GpuTilePoolDesc {
    /// GPU memory for the three texture arrays; layers = budgetBytes / bytesPerLayer.
    std::size_t budgetBytes = 0;
    /// Bytes (heights, block errors and ranges) uploaded per frame at most; see upload().
    std::size_t uploadBudgetBytesPerFrame = 0;
    /// Size of the pixel-buffer ring (extra to budgetBytes); 0 picks
    /// 2 × max(uploadBudgetBytesPerFrame, one tile).
    std::size_t ringBytes = 0;
};

/// Counters of the current frame, reset by beginFrame().
struct GpuTilePoolFrameStats {
    int uploads = 0;
    std::size_t bytesUploaded = 0;
    int uploadsDeferred = 0;  ///< refused: frame budget used, or the ring full of this frame
    int ringStalls = 0;       ///< times the CPU waited for the GPU to free ring bytes
    int evictions = 0;        ///< layers taken from patches by allocateEvicting()
};

/// What allocateEvicting() did: the layer now mapped to the patch, and the patch that
/// lost it, if a layer had to be taken from one.
struct GpuTileAllocation {
    int layer = -1;
    std::optional<io::PatchId> evicted;
};

/// Owns the tile texture arrays and the upload ring; maps resident patches to layers.
/// Everything here is render thread only: it owns GL objects and is not thread-safe.
/// allocate/release/upload/beginFrame/endFrame do not allocate memory after construction.
class GpuTilePool {
public:
    /// Bytes of one layer: heights R32F tileSamples² + block errors RGBA32F blocksPerSide² +
    /// block height ranges RG32F blocksPerSide².
    static std::size_t bytesPerLayer(const io::PyramidLayout& layout);

    /// Creates the texture arrays (immutable storage) and the ring. Errors: a budget below
    /// one layer, texture sizes beyond GL limits, a ring that cannot be mapped. Layers are
    /// clamped to GL_MAX_ARRAY_TEXTURE_LAYERS. Render thread only.
    static Result<GpuTilePool> create(const io::PyramidLayout& layout, const GpuTilePoolDesc& desc);

    GpuTilePool() = default;
    ~GpuTilePool();
    GpuTilePool(GpuTilePool&&) noexcept = default;
    GpuTilePool& operator=(GpuTilePool&&) noexcept = default;
    GpuTilePool(const GpuTilePool&) = delete;
    GpuTilePool& operator=(const GpuTilePool&) = delete;

    /// A layer for `id`, not yet resident; the same layer again when id already has one;
    /// nullopt when every layer is taken (the caller evicts and retries). Render thread only.
    std::optional<int> allocate(const io::PatchId& id);
    /// Like allocate(), but when every layer is taken, takes the layer of the least recently
    /// used patch that the current frame has not used (touch(), allocate(), upload()); a
    /// patch the current frame uses is never evicted, so nothing it draws is released.
    /// nullopt when every layer is used by this frame. Render thread only.
    std::optional<GpuTileAllocation> allocateEvicting(const io::PatchId& id);
    /// Marks id's layer as used by the current frame (id must hold one): it will not be
    /// evicted before the next beginFrame(). Render thread only.
    void touch(const io::PatchId& id);
    /// Frees id's layer; id must hold one (TERRAIN_ASSERT). Render thread only.
    void release(const io::PatchId& id);
    /// Keeps id's layer from eviction until unpin(), whatever frames use: the LOD tree pins
    /// the patches it holds, so drawing them needs no per-frame touch. id must hold a
    /// layer and not be pinned. Render thread only.
    void pin(const io::PatchId& id);
    /// Makes a pinned layer evictable again, as the most recently used. Render thread only.
    void unpin(const io::PatchId& id);
    bool isPinned(const io::PatchId& id) const;
    /// Layers pinned now. Render thread only.
    int pinnedCount() const { return m_pinnedCount; }
    /// Render thread only.
    std::optional<int> layerOf(const io::PatchId& id) const;
    /// Allocated and its upload issued (GL orders later draws after it). Render thread only.
    bool isResident(const io::PatchId& id) const;
    /// The summary of a resident patch (bounds and error, from its record), or null.
    /// Render thread only.
    const io::PatchInfo* info(const io::PatchId& id) const;
    /// The largest finite block error λ(d) (all blocks, d = 1..4) of a resident patch,
    /// metres, from its uploaded record; nullopt unless resident. With Err(P) it bounds the
    /// patch's drawn Λ (SkirtDepth.h): an infinite λ(d) is never drawn. Render thread only.
    std::optional<float> maxBlockErrorM(const io::PatchId& id) const;
    /// io::sampleRises of a resident patch's uploaded heights (apron included); nullopt
    /// unless resident. Render thread only.
    std::optional<io::SampleRises> sampleRises(const io::PatchId& id) const;
    /// io::coarseCellErrors of a resident patch, from its uploaded record: for every cell of
    /// 2^k × 2^k blocks, k = 1.., how far it may lie from the patch's own surface when drawn
    /// as one quad at factor 1 (add Err(P)). Empty unless resident, or when the layout has
    /// no coarse cells. Render thread only.
    std::span<const float> coarseCellErrorsM(const io::PatchId& id) const;
    /// The patch holding `layer`, or nullopt when the layer is free. Render thread only.
    std::optional<io::PatchId> patchOnLayer(int layer) const;

    /// Copies the record's heights, block errors and blocks' height ranges
    /// (io::blockHeightRanges, worked out here) into the ring and issues the texture
    /// copies into its layer (record.id must be allocated, sizes must match the layout:
    /// both TERRAIN_ASSERT; the reader validates tiles against the layout). The no-data
    /// mask is not uploaded. Returns false, uploading nothing, when this frame's byte
    /// budget is used (the first upload of a frame always fits the budget) or the ring is
    /// full of this frame's uploads: retry next frame. Render thread only.
    bool upload(const io::PatchRecord& record);

    /// Starts a new frame (see frame()): resets the frame budget and counters; retires
    /// fences the GPU has passed. Render thread only.
    void beginFrame();
    /// Fences this frame's uploads so their ring bytes are reused only once the GPU has
    /// read them. Render thread only.
    void endFrame();

    /// Whether one more upload fits this frame's byte budget (the ring may still refuse it).
    bool uploadBudgetLeft() const {
        return m_stats.bytesUploaded == 0 ||
               m_stats.bytesUploaded + uploadBytesPerTile() <= m_uploadBudgetBytes;
    }
    void setUploadBudgetBytesPerFrame(std::size_t bytes) { m_uploadBudgetBytes = bytes; }
    std::size_t uploadBudgetBytesPerFrame() const { return m_uploadBudgetBytes; }
    std::size_t ringBytes() const { return m_ring.sizeBytes(); }
    /// Bytes one upload() adds to the frame's total.
    std::size_t uploadBytesPerTile() const { return m_heightBytes + m_errorBytes + m_rangeBytes; }

    int layersUsed() const { return m_freeList.usedCount(); }
    int layersFree() const { return m_freeList.freeCount(); }
    int capacity() const { return m_freeList.capacity(); }
    const GpuTilePoolFrameStats& frameStats() const { return m_stats; }
    /// Frames begun so far; layers used in the current one are safe from eviction.
    std::uint64_t frame() const { return m_frame; }

    const gl::Texture& heights() const { return m_heights; }
    const gl::Texture& blockErrors() const { return m_blockErrors; }
    /// Per layer, each block's lowest and highest sample (RG32F, a texel a block): the box
    /// the control stage bounds the block's error over (surface_plane.glsl, blocksBoxM).
    const gl::Texture& blockRanges() const { return m_blockRanges; }

    /// The first broken invariant, described, or nullopt: the free list's own, every
    /// mapped patch on an allocated layer of its own, one patch per allocated layer, and
    /// exactly the allocated layers that are not pinned in the LRU order.
    /// O(capacity): for tests and the stress tool.
    std::optional<std::string> checkInvariants() const;

private:
    struct Slot {
        int layer = -1;
        bool resident = false;
        io::PatchInfo info;  // from the uploaded record
    };
    using SlotMap = std::unordered_map<io::PatchId, Slot, io::PatchIdHash>;

    /// A frame's uploads: the GPU has read their ring bytes once `fence` is signalled.
    struct FencedUploads {
        gl::Fence fence;
        std::uint64_t ringEnd = 0;  ///< ring position just past the fenced uploads
    };
    static constexpr int kMaxFences = 8;

    std::optional<std::size_t> reserveRing(std::size_t bytes);
    void retireOldestFence(bool wait);

    LayerFreeList m_freeList{0};
    LayerLru m_lru{0};                                     // allocated layers that are not pinned
    std::vector<std::uint8_t> m_pinned;                    // per layer
    mutable std::vector<std::uint8_t> m_invariantScratch;  // per layer, for checkInvariants()
    int m_pinnedCount = 0;
    std::vector<io::PatchId> m_layerPatch;   // per allocated layer, its patch
    std::vector<float> m_maxBlockErrorM;     // per layer, of its last upload
    std::vector<io::SampleRises> m_sampleRises;  // per layer, of its last upload
    int m_coarseCellsPerLayer = 0;           // io::coarseCellCount of the layout
    std::vector<float> m_coarseCellErrorsM;  // that many per layer, of its last upload
    std::vector<float> m_cornerScratch;      // io::coarseCellErrors' block-corner grid
    std::uint64_t m_frame = 0;
    SlotMap m_slots;
    std::vector<SlotMap::node_type> m_spareNodes;  // reused by allocate(): no node allocation
    gl::Texture m_heights;
    gl::Texture m_blockErrors;
    gl::Texture m_blockRanges;
    std::vector<io::HeightRange> m_rangeScratch;  // one upload's block ranges
    int m_tileSamples = 0;
    int m_blocksPerSide = 0;
    std::size_t m_heightBytes = 0;
    std::size_t m_errorBytes = 0;
    std::size_t m_rangeBytes = 0;

    gl::Buffer m_ring;
    std::byte* m_ringData = nullptr;  // persistent, coherent mapping of m_ring
    std::uint64_t m_ringHead = 0;     // total bytes reserved (positions grow, wrap by modulo)
    std::uint64_t m_ringTail = 0;     // bytes before this the GPU has finished reading
    std::uint64_t m_ringFenced = 0;   // bytes before this are covered by a fence
    std::array<FencedUploads, kMaxFences> m_fences;
    int m_fenceFirst = 0;
    int m_fenceCount = 0;

    std::size_t m_uploadBudgetBytes = 0;
    GpuTilePoolFrameStats m_stats;
};

}  // namespace terrain::cache
