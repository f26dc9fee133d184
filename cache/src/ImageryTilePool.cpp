// ImageryTilePool: layer bookkeeping as GpuTilePool's; uploads are client-memory texture
// copies (the driver stages them) of each level, the mips as the I/O thread made them.
#include "terrain/cache/ImageryTilePool.h"

#include "terrain/base/Assert.h"
#include "terrain/gl/DriverWorkarounds.h"
#include "terrain/gl/GlInfo.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstddef>
#include <span>
#include <utility>

namespace terrain::cache {
namespace {

constexpr int texelsAtMip(int mip) { return io::kImageryTileTexels >> mip; }

constexpr std::size_t bytesAtMip(int mip) {
    return static_cast<std::size_t>(texelsAtMip(mip)) * static_cast<std::size_t>(texelsAtMip(mip)) *
           4;
}

std::string tileName(const io::TileKey& key) {
    return fmt::format("imagery layer {} tile L{} ({}, {})", key.imageryLayer, key.id.level,
                       key.id.x, key.id.y);
}

}  // namespace

static_assert(io::kImageryTileMips == 3, "ImageryTilePool uploads exactly three mips");

std::size_t ImageryTilePool::bytesPerLayer() {
    std::size_t bytes = 0;
    for (int mip = 0; mip < io::kImageryTileMips; ++mip) bytes += bytesAtMip(mip);
    return bytes;
}

Result<ImageryTilePool> ImageryTilePool::create(const ImageryTilePoolDesc& desc) {
    const std::size_t layerBytes = bytesPerLayer();
    if (desc.budgetBytes < layerBytes)
        return Error{
            fmt::format("ImageryTilePool: GPU budget of {} bytes is below one imagery "
                        "tile ({} bytes with its mips)",
                        desc.budgetBytes, layerBytes)};
    GLint maxLayers = 0;
    glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &maxLayers);
    if (maxLayers < 1)
        return Error{fmt::format("ImageryTilePool: GL_MAX_ARRAY_TEXTURE_LAYERS is {}", maxLayers)};
    const auto layers = static_cast<int>(
        std::min(desc.budgetBytes / layerBytes, static_cast<std::size_t>(maxLayers)));

    ImageryTilePool pool;
    auto texture = gl::Texture::create2DArray({.internalFormat = GL_SRGB8_ALPHA8,
                                               .width = io::kImageryTileTexels,
                                               .height = io::kImageryTileTexels,
                                               .layers = layers,
                                               .levels = io::kImageryTileMips},
                                              "imagery tiles");
    if (!texture) return Error{"ImageryTilePool: " + texture.error().message};
    pool.m_texture = std::move(texture).value();
    // Trilinear within a tile's mips, never past the last one that keeps whole border
    // texels (ImageryTile.h); the draw takes the parent tile beyond it.
    pool.m_texture.setSampling(GL_LINEAR_MIPMAP_LINEAR, GL_LINEAR, GL_CLAMP_TO_EDGE);
    pool.m_texture.setMaxLevel(io::kImageryTileMips - 1);
    pool.m_maxAnisotropy =
        std::clamp(desc.maxAnisotropy, 1.0f, gl::textureAnisotropyWorthFiltering());
    pool.m_texture.setMaxAnisotropy(pool.m_maxAnisotropy);

    pool.m_uploadBudgetBytes = desc.uploadBudgetBytesPerFrame;
    pool.m_freeList = LayerFreeList(layers);
    pool.m_lru = LayerLru(layers);
    const auto capacity = static_cast<std::size_t>(layers);
    pool.m_layerTile.resize(capacity);
    pool.m_invariantScratch.assign(capacity, 0);
    pool.m_slots.reserve(capacity);
    pool.m_spareNodes.reserve(capacity);
    return pool;
}

std::optional<ImageryTileAllocation> ImageryTilePool::allocateEvicting(const io::TileKey& key) {
    TERRAIN_ASSERT(key.isImagery(), "ImageryTilePool: a key of the heights");
    if (const auto found = m_slots.find(key); found != m_slots.end()) {
        m_lru.touch(found->second.layer, m_frame);
        return ImageryTileAllocation{.layer = found->second.layer, .evicted = std::nullopt};
    }
    std::optional<io::TileKey> evicted;
    if (m_freeList.freeCount() == 0) {
        const std::optional<int> oldest = m_lru.leastRecent();
        if (!oldest || m_lru.lastUsedFrame(*oldest) >= m_frame) return std::nullopt;
        evicted = m_layerTile[static_cast<std::size_t>(*oldest)];
        release(*evicted);
        ++m_stats.evictions;
    }
    const std::optional<int> layer = m_freeList.allocate();
    TERRAIN_ASSERT(layer.has_value(), "ImageryTilePool: no layer after an eviction");
    m_lru.insert(*layer, m_frame);
    m_layerTile[static_cast<std::size_t>(*layer)] = key;
    const Slot slot{.layer = *layer, .resident = false, .info = {}};
    if (!m_spareNodes.empty()) {
        SlotMap::node_type node = std::move(m_spareNodes.back());
        m_spareNodes.pop_back();
        node.key() = key;
        node.mapped() = slot;
        m_slots.insert(std::move(node));
    } else {
        m_slots.emplace(key, slot);  // below capacity: reserved, never rehashes
    }
    return ImageryTileAllocation{.layer = *layer, .evicted = evicted};
}

void ImageryTilePool::touch(const io::TileKey& key) {
    const auto found = m_slots.find(key);
    TERRAIN_ASSERT(found != m_slots.end(), "ImageryTilePool::touch of a tile without a layer");
    m_lru.touch(found->second.layer, m_frame);
}

void ImageryTilePool::release(const io::TileKey& key) {
    const auto found = m_slots.find(key);
    TERRAIN_ASSERT(found != m_slots.end(), "ImageryTilePool::release of a tile without a layer");
    m_freeList.release(found->second.layer);
    m_lru.remove(found->second.layer);
    // A later upload into the layer is ordered after any draw that sampled it: GL executes
    // commands in submission order.
    m_spareNodes.push_back(m_slots.extract(found));
}

bool ImageryTilePool::upload(const io::TileKey& key, const io::ImageryTile& tile) {
    const auto found = m_slots.find(key);
    TERRAIN_ASSERT(found != m_slots.end(), "ImageryTilePool::upload of a tile without a layer");
    TERRAIN_ASSERT(tile.info.present && tile.rgba.size() == io::kImageryTileBytes &&
                       tile.mips.size() == io::kImageryMipChainBytes,
                   "ImageryTilePool::upload of a tile without its texels and mips");
    if (!uploadBudgetLeft()) {
        ++m_stats.uploadsDeferred;
        return false;
    }
    const int layer = found->second.layer;
    for (int mip = 0; mip < io::kImageryTileMips; ++mip) {
        const std::span<const std::uint8_t> level = io::imageryMip(tile, mip);
        const gl::TextureRegion region{.level = mip,
                                       .x = 0,
                                       .y = 0,
                                       .layer = layer,
                                       .width = texelsAtMip(mip),
                                       .height = texelsAtMip(mip),
                                       .layers = 1};
        m_texture.upload(region, GL_RGBA, GL_UNSIGNED_BYTE, std::as_bytes(level));
    }
    found->second.resident = true;
    found->second.info = tile.info;
    m_lru.touch(layer, m_frame);
    ++m_stats.uploads;
    m_stats.bytesUploaded += bytesPerLayer();
    return true;
}

void ImageryTilePool::beginFrame() {
    m_stats = {};
    ++m_frame;
}

std::optional<int> ImageryTilePool::layerOf(const io::TileKey& key) const {
    const auto found = m_slots.find(key);
    if (found == m_slots.end()) return std::nullopt;
    return found->second.layer;
}

bool ImageryTilePool::isResident(const io::TileKey& key) const {
    const auto found = m_slots.find(key);
    return found != m_slots.end() && found->second.resident;
}

const io::ImageryTileInfo* ImageryTilePool::info(const io::TileKey& key) const {
    const auto found = m_slots.find(key);
    if (found == m_slots.end() || !found->second.resident) return nullptr;
    return &found->second.info;
}

std::optional<io::TileKey> ImageryTilePool::tileOnLayer(int layer) const {
    TERRAIN_ASSERT(layer >= 0 && layer < capacity(), "ImageryTilePool: layer out of range");
    if (!m_freeList.isAllocated(layer)) return std::nullopt;
    return m_layerTile[static_cast<std::size_t>(layer)];
}

std::optional<std::string> ImageryTilePool::checkInvariants() const {
    if (auto broken = m_freeList.checkInvariants()) return "free list: " + *broken;
    if (static_cast<int>(m_slots.size()) != m_freeList.usedCount())
        return fmt::format("{} tiles mapped but {} layers in use", m_slots.size(),
                           m_freeList.usedCount());
    std::vector<std::uint8_t>& seen = m_invariantScratch;
    std::fill(seen.begin(), seen.end(), std::uint8_t{0});
    for (const auto& [key, slot] : m_slots) {
        if (slot.layer < 0 || slot.layer >= capacity())
            return fmt::format("{} maps to layer {}, out of range", tileName(key), slot.layer);
        if (!m_freeList.isAllocated(slot.layer))
            return fmt::format("{} maps to layer {}, which is free", tileName(key), slot.layer);
        auto& mark = seen[static_cast<std::size_t>(slot.layer)];
        if (mark != 0) return fmt::format("layer {} is mapped to two tiles", slot.layer);
        mark = 1;
        if (!(m_layerTile[static_cast<std::size_t>(slot.layer)] == key))
            return fmt::format("{} maps to layer {}, which records another tile", tileName(key),
                               slot.layer);
        if (!m_lru.contains(slot.layer))
            return fmt::format("{} holds layer {}, which is missing from the LRU order",
                               tileName(key), slot.layer);
    }
    if (m_lru.size() != m_freeList.usedCount())
        return fmt::format("{} layers in the LRU order but {} in use", m_lru.size(),
                           m_freeList.usedCount());
    return std::nullopt;
}

}  // namespace terrain::cache
