// ImageryTilePool: the imagery tiles resident on the GPU (issue 47), one layer per tile in a
// GL_SRGB8_ALPHA8 2D texture array of kImageryTileTexels² tiles with kImageryTileMips mip
// levels (made by the I/O thread, io::makeImageryMips' alpha-weighted box filter), layers
// from a byte budget, handed out by a LayerFreeList and evicted least recently used
// (LayerLru), never a tile the current frame uses; uploads within a per-frame byte budget.
// Tiles of every imagery layer share the array: a key is (imagery layer, patch).
// Yusov & Shevtsov 2011, §5: texture arrays and a list of unused subresources, as for the
// heights (GpuTilePool).
#pragma once

#include "terrain/base/Result.h"
#include "terrain/cache/LayerFreeList.h"
#include "terrain/cache/LayerLru.h"
#include "terrain/gl/Texture.h"
#include "terrain/iothread/TileKey.h"
#include "terrain/pyramid/ImageryTile.h"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

namespace terrain::cache {

struct ImageryTilePoolDesc {
    /// GPU memory of the texture array; layers = budgetBytes / bytesPerLayer() (clamped
    /// to GL_MAX_ARRAY_TEXTURE_LAYERS).
    std::size_t budgetBytes = 0;
    /// Bytes (all mips) uploaded per frame at most; the first upload of a frame always fits.
    std::size_t uploadBudgetBytesPerFrame = 0;
    /// Anisotropic filtering wanted, clamped to what the context filters with
    /// (gl::textureAnisotropyWorthFiltering: 1 where it has none, and on llvmpipe).
    float maxAnisotropy = 16.0f;
};

/// Counters of the current frame, reset by beginFrame().
struct ImageryTilePoolFrameStats {
    int uploads = 0;
    std::size_t bytesUploaded = 0;
    int uploadsDeferred = 0;  ///< refused: the frame's upload budget was used
    int evictions = 0;        ///< layers taken from tiles by allocateEvicting()
};

/// What allocateEvicting() did: the layer now mapped to the tile, and the tile that lost
/// it, if a layer had to be taken from one.
struct ImageryTileAllocation {
    int layer = -1;
    std::optional<io::TileKey> evicted;
};

/// Render thread only: owns GL objects, not thread-safe. allocate/release/touch/upload/
/// beginFrame do not allocate memory after create().
class ImageryTilePool {
public:
    /// GPU bytes of one layer, every mip level included (RGBA8: 256² + 128² + 64² texels).
    static std::size_t bytesPerLayer();

    /// Creates the texture array (immutable storage; trilinear, anisotropic, clamped to
    /// the edge; GL_TEXTURE_MAX_LEVEL kImageryTileMips − 1). Errors: a budget below one
    /// layer, a texture the context refuses. Render thread only.
    static Result<ImageryTilePool> create(const ImageryTilePoolDesc& desc);

    ImageryTilePool() = default;
    ImageryTilePool(ImageryTilePool&&) noexcept = default;
    ImageryTilePool& operator=(ImageryTilePool&&) noexcept = default;
    ImageryTilePool(const ImageryTilePool&) = delete;
    ImageryTilePool& operator=(const ImageryTilePool&) = delete;

    /// A layer for `key` (its own again when it has one), marked used this frame; when
    /// every layer is taken, the layer of the least recently used tile the current frame
    /// has not used (touch(), allocateEvicting(), upload()); nullopt when every layer is used
    /// by this frame. Render thread only.
    std::optional<ImageryTileAllocation> allocateEvicting(const io::TileKey& key);
    /// Marks key's layer used by the current frame (key must hold one): it is not evicted
    /// before the next beginFrame(). Render thread only.
    void touch(const io::TileKey& key);
    /// Frees key's layer; key must hold one. Render thread only.
    void release(const io::TileKey& key);

    /// Uploads `tile` (present, with kImageryTileBytes of texels and its kImageryMipChainBytes
    /// of mips, io::makeImageryMips: TERRAIN_ASSERT) into key's layer (allocated:
    /// TERRAIN_ASSERT), every mip level. Returns false, uploading nothing, when this frame's
    /// upload budget is used: retry next frame. Render thread only.
    bool upload(const io::TileKey& key, const io::ImageryTile& tile);

    /// Starts a frame: resets the upload budget and counters; tiles used by the previous
    /// frames become evictable. Render thread only.
    void beginFrame();

    std::optional<int> layerOf(const io::TileKey& key) const;
    /// Allocated and uploaded (GL orders later draws after the upload).
    bool isResident(const io::TileKey& key) const;
    /// The info of a resident tile, or null.
    const io::ImageryTileInfo* info(const io::TileKey& key) const;
    /// The tile holding `layer`, or nullopt when it is free.
    std::optional<io::TileKey> tileOnLayer(int layer) const;

    bool uploadBudgetLeft() const {
        return m_stats.bytesUploaded == 0 ||
               m_stats.bytesUploaded + bytesPerLayer() <= m_uploadBudgetBytes;
    }
    std::size_t uploadBudgetBytesPerFrame() const { return m_uploadBudgetBytes; }
    int layersUsed() const { return m_freeList.usedCount(); }
    int layersFree() const { return m_freeList.freeCount(); }
    int capacity() const { return m_freeList.capacity(); }
    /// GPU bytes of the layers holding a tile now.
    std::size_t bytesUsed() const {
        return static_cast<std::size_t>(layersUsed()) * bytesPerLayer();
    }
    const ImageryTilePoolFrameStats& frameStats() const { return m_stats; }
    std::uint64_t frame() const { return m_frame; }
    /// The anisotropy the texture samples with (1: none).
    float maxAnisotropy() const { return m_maxAnisotropy; }

    /// The texture array the draw samples (GL_TEXTURE_2D_ARRAY, GL_SRGB8_ALPHA8); invalid
    /// for a default-constructed pool.
    const gl::Texture& texture() const { return m_texture; }

    /// The first broken invariant, described, or nullopt: the free list's own, every mapped
    /// tile on an allocated layer of its own, one tile per allocated layer, and exactly the
    /// allocated layers in the LRU order. O(capacity): for tests and the stress tool.
    std::optional<std::string> checkInvariants() const;

private:
    struct Slot {
        int layer = -1;
        bool resident = false;
        io::ImageryTileInfo info;
    };
    using SlotMap = std::unordered_map<io::TileKey, Slot, io::TileKeyHash>;

    LayerFreeList m_freeList{0};
    LayerLru m_lru{0};
    std::vector<io::TileKey> m_layerTile;                  // per allocated layer, its tile
    mutable std::vector<std::uint8_t> m_invariantScratch;  // per layer
    SlotMap m_slots;
    std::vector<SlotMap::node_type> m_spareNodes;  // reused: no node allocation
    std::uint64_t m_frame = 0;
    gl::Texture m_texture;
    float m_maxAnisotropy = 1.0f;
    std::size_t m_uploadBudgetBytes = 0;
    ImageryTilePoolFrameStats m_stats;
};

}  // namespace terrain::cache
