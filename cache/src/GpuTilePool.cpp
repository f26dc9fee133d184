// GpuTilePool: layer bookkeeping and fenced uploads through a persistent-mapped ring.
#include "terrain/cache/GpuTilePool.h"

#include "terrain/base/Assert.h"
#include "terrain/gl/PixelStoreScope.h"
#include "terrain/pyramid/CoarseCellErrors.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <utility>

namespace terrain::cache {
namespace {

// Unpack-buffer offsets must be multiples of the pixel component size (4 for GL_FLOAT);
// 16 keeps every RGBA32F texel aligned as well.
constexpr std::size_t kRingAlignment = 16;
constexpr GLbitfield kRingFlags = GL_MAP_WRITE_BIT | GL_MAP_PERSISTENT_BIT | GL_MAP_COHERENT_BIT;

std::size_t alignUp(std::size_t value, std::size_t alignment) {
    return (value + alignment - 1) / alignment * alignment;
}

std::size_t squared(int side) {
    return static_cast<std::size_t>(side) * static_cast<std::size_t>(side);
}

}  // namespace

GpuTilePool::~GpuTilePool() = default;  // deleting the ring buffer also unmaps it

std::size_t GpuTilePool::bytesPerLayer(const io::PyramidLayout& layout) {
    return squared(layout.tileSamples()) * sizeof(float) +
           squared(layout.blocksPerSide()) * (sizeof(io::BlockErrors) + sizeof(io::HeightRange));
}

Result<GpuTilePool> GpuTilePool::create(const io::PyramidLayout& layout,
                                        const GpuTilePoolDesc& desc) {
    const std::size_t layerBytes = bytesPerLayer(layout);
    if (desc.budgetBytes < layerBytes) {
        return Error{"GpuTilePool: GPU budget of " + std::to_string(desc.budgetBytes) +
                     " bytes is below one tile layer (" + std::to_string(layerBytes) + " bytes)"};
    }
    GLint maxLayers = 0;
    glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &maxLayers);
    if (maxLayers < 1) {
        return Error{"GpuTilePool: GL_MAX_ARRAY_TEXTURE_LAYERS is " + std::to_string(maxLayers)};
    }
    const auto layers = static_cast<int>(
        std::min(desc.budgetBytes / layerBytes, static_cast<std::size_t>(maxLayers)));

    GpuTilePool pool;
    pool.m_tileSamples = layout.tileSamples();
    pool.m_blocksPerSide = layout.blocksPerSide();
    pool.m_heightBytes = squared(pool.m_tileSamples) * sizeof(float);
    pool.m_errorBytes = squared(pool.m_blocksPerSide) * sizeof(io::BlockErrors);
    pool.m_rangeBytes = squared(pool.m_blocksPerSide) * sizeof(io::HeightRange);
    pool.m_rangeScratch.resize(squared(pool.m_blocksPerSide));
    pool.m_uploadBudgetBytes = desc.uploadBudgetBytesPerFrame;

    // One texture array of `side`² texels a layer, a layer per patch.
    const auto layerArray = [&](GLenum format, int side, const char* name,
                                gl::Texture& out) -> Status {
        auto created = gl::Texture::create2DArray(
            {.internalFormat = format, .width = side, .height = side, .layers = layers}, name);
        if (!created) return Error{"GpuTilePool: " + created.error().message};
        out = std::move(created).value();
        return {};
    };
    if (Status made = layerArray(GL_R32F, pool.m_tileSamples, "tile pool heights", pool.m_heights);
        !made)
        return made.error();
    if (Status made = layerArray(GL_RGBA32F, pool.m_blocksPerSide, "tile pool block errors",
                                 pool.m_blockErrors);
        !made)
        return made.error();
    if (Status made = layerArray(GL_RG32F, pool.m_blocksPerSide, "tile pool block height ranges",
                                 pool.m_blockRanges);
        !made)
        return made.error();
    // Nearest texel fetches: heights and errors are data, not images to filter.
    pool.m_blockErrors.setSampling(GL_NEAREST, GL_NEAREST, GL_CLAMP_TO_EDGE);
    pool.m_blockRanges.setSampling(GL_NEAREST, GL_NEAREST, GL_CLAMP_TO_EDGE);

    const std::size_t tileRingBytes = alignUp(pool.m_heightBytes, kRingAlignment) +
                                      alignUp(pool.m_errorBytes, kRingAlignment) +
                                      alignUp(pool.m_rangeBytes, kRingAlignment);
    std::size_t ringBytes = desc.ringBytes != 0
                                ? desc.ringBytes
                                : 2 * std::max(desc.uploadBudgetBytesPerFrame, tileRingBytes);
    ringBytes = alignUp(ringBytes, kRingAlignment);
    if (ringBytes < tileRingBytes) {
        return Error{"GpuTilePool: upload ring of " + std::to_string(ringBytes) +
                     " bytes cannot hold one tile (" + std::to_string(tileRingBytes) + " bytes)"};
    }
    pool.m_ring = gl::Buffer::create(ringBytes, kRingFlags, "tile pool upload ring");
    void* mapped =
        glMapNamedBufferRange(pool.m_ring.id(), 0, static_cast<GLsizeiptr>(ringBytes), kRingFlags);
    if (mapped == nullptr) {
        return Error{"GpuTilePool: cannot map the upload ring persistently (" +
                     std::to_string(ringBytes) + " bytes)"};
    }
    pool.m_ringData = static_cast<std::byte*>(mapped);

    pool.m_freeList = LayerFreeList(layers);
    pool.m_lru = LayerLru(layers);
    pool.m_pinned.assign(static_cast<std::size_t>(layers), 0);
    pool.m_invariantScratch.assign(static_cast<std::size_t>(layers), 0);
    pool.m_layerPatch.resize(static_cast<std::size_t>(layers));
    pool.m_maxBlockErrorM.assign(static_cast<std::size_t>(layers), 0.0f);
    pool.m_sampleRises.assign(static_cast<std::size_t>(layers), io::SampleRises{});
    pool.m_coarseCellsPerLayer = io::coarseCellCount(layout.patchQuads(), layout.blockQuads());
    pool.m_coarseCellErrorsM.assign(
        static_cast<std::size_t>(layers) * static_cast<std::size_t>(pool.m_coarseCellsPerLayer),
        0.0f);
    pool.m_cornerScratch.assign(squared(pool.m_blocksPerSide + 1), 0.0f);
    const auto capacity = static_cast<std::size_t>(layers);
    pool.m_slots.reserve(capacity);
    pool.m_spareNodes.reserve(capacity);
    return pool;
}

std::optional<int> GpuTilePool::allocate(const io::PatchId& id) {
    if (const auto found = m_slots.find(id); found != m_slots.end()) {
        return found->second.layer;
    }
    const std::optional<int> maybeLayer = m_freeList.allocate();
    if (!maybeLayer) {
        return std::nullopt;
    }
    const Slot slot{.layer = *maybeLayer, .resident = false, .info = {}};
    m_lru.insert(*maybeLayer, m_frame);
    m_layerPatch[static_cast<std::size_t>(*maybeLayer)] = id;
    if (!m_spareNodes.empty()) {
        // Reuse a node released earlier so steady-state allocation never touches the heap.
        SlotMap::node_type node = std::move(m_spareNodes.back());
        m_spareNodes.pop_back();
        node.key() = id;
        node.mapped() = slot;
        m_slots.insert(std::move(node));
    } else {
        m_slots.emplace(id, slot);
    }
    return maybeLayer;
}

std::optional<GpuTileAllocation> GpuTilePool::allocateEvicting(const io::PatchId& id) {
    if (const auto found = m_slots.find(id); found != m_slots.end()) {
        const int layer = found->second.layer;
        if (m_lru.contains(layer)) m_lru.touch(layer, m_frame);
        return GpuTileAllocation{.layer = layer, .evicted = std::nullopt};
    }
    std::optional<io::PatchId> evicted;
    if (m_freeList.freeCount() == 0) {
        const std::optional<int> oldest = m_lru.leastRecent();
        if (!oldest || m_lru.lastUsedFrame(*oldest) >= m_frame) {
            return std::nullopt;  // every layer is used by this frame
        }
        evicted = m_layerPatch[static_cast<std::size_t>(*oldest)];
        release(*evicted);
        ++m_stats.evictions;
    }
    const std::optional<int> layer = allocate(id);
    TERRAIN_ASSERT(layer.has_value(), "GpuTilePool: no layer after an eviction");
    return GpuTileAllocation{.layer = *layer, .evicted = evicted};
}

void GpuTilePool::touch(const io::PatchId& id) {
    const auto found = m_slots.find(id);
    TERRAIN_ASSERT(found != m_slots.end(), "GpuTilePool::touch of a patch without a layer");
    const int layer = found->second.layer;
    if (m_lru.contains(layer)) m_lru.touch(layer, m_frame);  // pinned layers are not in it
}

void GpuTilePool::pin(const io::PatchId& id) {
    const auto found = m_slots.find(id);
    TERRAIN_ASSERT(found != m_slots.end(), "GpuTilePool::pin of a patch without a layer");
    const auto layer = static_cast<std::size_t>(found->second.layer);
    TERRAIN_ASSERT(m_pinned[layer] == 0, "GpuTilePool::pin of a pinned patch");
    m_lru.remove(found->second.layer);
    m_pinned[layer] = 1;
    ++m_pinnedCount;
}

void GpuTilePool::unpin(const io::PatchId& id) {
    const auto found = m_slots.find(id);
    TERRAIN_ASSERT(found != m_slots.end(), "GpuTilePool::unpin of a patch without a layer");
    const auto layer = static_cast<std::size_t>(found->second.layer);
    TERRAIN_ASSERT(m_pinned[layer] != 0, "GpuTilePool::unpin of a patch that is not pinned");
    m_pinned[layer] = 0;
    --m_pinnedCount;
    m_lru.insert(found->second.layer, m_frame);
}

bool GpuTilePool::isPinned(const io::PatchId& id) const {
    const auto found = m_slots.find(id);
    return found != m_slots.end() && m_pinned[static_cast<std::size_t>(found->second.layer)] != 0;
}

void GpuTilePool::release(const io::PatchId& id) {
    const auto found = m_slots.find(id);
    TERRAIN_ASSERT(found != m_slots.end(), "GpuTilePool::release of a patch without a layer");
    TERRAIN_ASSERT(m_pinned[static_cast<std::size_t>(found->second.layer)] == 0,
                   "GpuTilePool::release of a pinned patch");
    m_freeList.release(found->second.layer);
    m_lru.remove(found->second.layer);
    // A pending upload into this layer stays ordered before any later one: GL executes
    // texture copies in submission order.
    m_spareNodes.push_back(m_slots.extract(found));
}

std::optional<int> GpuTilePool::layerOf(const io::PatchId& id) const {
    const auto found = m_slots.find(id);
    if (found == m_slots.end()) {
        return std::nullopt;
    }
    return found->second.layer;
}

bool GpuTilePool::isResident(const io::PatchId& id) const {
    const auto found = m_slots.find(id);
    return found != m_slots.end() && found->second.resident;
}

const io::PatchInfo* GpuTilePool::info(const io::PatchId& id) const {
    const auto found = m_slots.find(id);
    if (found == m_slots.end() || !found->second.resident) {
        return nullptr;
    }
    return &found->second.info;
}

std::optional<float> GpuTilePool::maxBlockErrorM(const io::PatchId& id) const {
    const auto found = m_slots.find(id);
    if (found == m_slots.end() || !found->second.resident) return std::nullopt;
    return m_maxBlockErrorM[static_cast<std::size_t>(found->second.layer)];
}

std::optional<io::SampleRises> GpuTilePool::sampleRises(const io::PatchId& id) const {
    const auto found = m_slots.find(id);
    if (found == m_slots.end() || !found->second.resident) return std::nullopt;
    return m_sampleRises[static_cast<std::size_t>(found->second.layer)];
}

std::span<const float> GpuTilePool::coarseCellErrorsM(const io::PatchId& id) const {
    const auto found = m_slots.find(id);
    if (found == m_slots.end() || !found->second.resident) return {};
    const auto cells = static_cast<std::size_t>(m_coarseCellsPerLayer);
    return std::span(m_coarseCellErrorsM)
        .subspan(static_cast<std::size_t>(found->second.layer) * cells, cells);
}

std::optional<io::PatchId> GpuTilePool::patchOnLayer(int layer) const {
    TERRAIN_ASSERT(layer >= 0 && layer < capacity(), "GpuTilePool: layer out of range");
    if (!m_freeList.isAllocated(layer)) {
        return std::nullopt;
    }
    return m_layerPatch[static_cast<std::size_t>(layer)];
}

std::optional<std::size_t> GpuTilePool::reserveRing(std::size_t bytes) {
    const std::uint64_t size = m_ring.sizeBytes();
    TERRAIN_ASSERT(bytes <= size);
    std::uint64_t start = m_ringHead;
    if (start % size + bytes > size) {
        start += size - start % size;  // never split a tile across the end: wrap to 0
    }
    while (start + bytes - m_ringTail > size) {
        if (m_fenceCount == 0) {
            return std::nullopt;  // the ring is full of this frame's own, unfenced uploads
        }
        retireOldestFence(true);
        ++m_stats.ringStalls;
    }
    m_ringHead = start + bytes;
    return static_cast<std::size_t>(start % size);
}

void GpuTilePool::retireOldestFence(bool wait) {
    TERRAIN_ASSERT(m_fenceCount > 0);
    FencedUploads& oldest = m_fences[static_cast<std::size_t>(m_fenceFirst)];
    if (wait) oldest.fence.wait();
    m_ringTail = oldest.ringEnd;
    oldest.fence.reset();
    m_fenceFirst = (m_fenceFirst + 1) % kMaxFences;
    --m_fenceCount;
}

bool GpuTilePool::upload(const io::PatchRecord& record) {
    const auto found = m_slots.find(record.id);
    TERRAIN_ASSERT(found != m_slots.end(), "GpuTilePool::upload of a patch without a layer");
    TERRAIN_ASSERT(record.heights.size() == squared(m_tileSamples),
                   "GpuTilePool::upload: heights do not match the layout");
    TERRAIN_ASSERT(record.blockErrors.size() == squared(m_blocksPerSide),
                   "GpuTilePool::upload: block errors do not match the layout");

    const std::size_t tileBytes = uploadBytesPerTile();
    if (!uploadBudgetLeft()) {
        ++m_stats.uploadsDeferred;
        return false;
    }
    const std::size_t errorOffset = alignUp(m_heightBytes, kRingAlignment);
    const std::size_t rangeOffset = errorOffset + alignUp(m_errorBytes, kRingAlignment);
    const std::optional<std::size_t> maybeOffset =
        reserveRing(rangeOffset + alignUp(m_rangeBytes, kRingAlignment));
    if (!maybeOffset) {
        ++m_stats.uploadsDeferred;
        return false;
    }
    const std::size_t offset = *maybeOffset;
    std::memcpy(m_ringData + offset, record.heights.data(), m_heightBytes);
    std::memcpy(m_ringData + offset + errorOffset, record.blockErrors.data(), m_errorBytes);
    {
        const int patchSamples = m_tileSamples - 2;
        const io::GridView interior{record.heights.data() + m_tileSamples + 1, patchSamples,
                                    m_tileSamples};
        io::blockHeightRanges(interior, (patchSamples - 1) / m_blocksPerSide,
                              {record.info.minHeight, record.info.maxHeight}, m_rangeScratch);
        std::memcpy(m_ringData + offset + rangeOffset, m_rangeScratch.data(), m_rangeBytes);
    }

    const int layer = found->second.layer;
    {
        // Tight packing, and the caller's unpack binding and pixel-store state put back.
        const gl::PixelStoreScope pixelStore;
        glBindBuffer(GL_PIXEL_UNPACK_BUFFER, m_ring.id());
        // Pointers are offsets into the bound unpack buffer.
        glTextureSubImage3D(m_heights.id(), 0, 0, 0, layer, m_tileSamples, m_tileSamples, 1, GL_RED,
                            GL_FLOAT, reinterpret_cast<const void*>(offset));
        glTextureSubImage3D(m_blockErrors.id(), 0, 0, 0, layer, m_blocksPerSide, m_blocksPerSide, 1,
                            GL_RGBA, GL_FLOAT, reinterpret_cast<const void*>(offset + errorOffset));
        glTextureSubImage3D(m_blockRanges.id(), 0, 0, 0, layer, m_blocksPerSide, m_blocksPerSide, 1,
                            GL_RG, GL_FLOAT, reinterpret_cast<const void*>(offset + rangeOffset));
    }
    found->second.resident = true;
    found->second.info = record.info;
    // λ(d) = +∞ is a simplification too coarse to store (a half beyond 65,504 m: a globe
    // face's root tile at d ≥ 3, where its blocks' chords sag tens of kilometres under the
    // ellipsoid). The control stage never picks it (∞ · px/m is never below ε), so it bounds
    // nothing drawn; counting it made every skirt of the frame infinitely deep, a vertex at
    // infinity, and no skirt was drawn at all.
    float maxBlockError = 0.0f;
    for (const io::BlockErrors& errors : record.blockErrors) {
        for (const float lambda : errors)
            if (std::isfinite(lambda)) maxBlockError = std::max(maxBlockError, lambda);
    }
    m_maxBlockErrorM[static_cast<std::size_t>(layer)] = maxBlockError;
    m_sampleRises[static_cast<std::size_t>(layer)] =
        io::sampleRises({record.heights.data(), m_tileSamples, m_tileSamples});
    if (m_coarseCellsPerLayer > 0) {
        // A few microseconds: the block-corner grid is (K + 1)² samples.
        const auto cells = static_cast<std::size_t>(m_coarseCellsPerLayer);
        const int patchSamples = m_tileSamples - 2;
        const io::GridView interior{record.heights.data() + m_tileSamples + 1, patchSamples,
                                    m_tileSamples};
        io::coarseCellErrors(
            interior, (patchSamples - 1) / m_blocksPerSide, record.blockErrors, m_cornerScratch,
            std::span(m_coarseCellErrorsM).subspan(static_cast<std::size_t>(layer) * cells, cells));
    }
    if (m_lru.contains(layer)) m_lru.touch(layer, m_frame);
    ++m_stats.uploads;
    m_stats.bytesUploaded += tileBytes;
    return true;
}

void GpuTilePool::beginFrame() {
    m_stats = {};
    ++m_frame;
    while (m_fenceCount > 0) {
        if (!m_fences[static_cast<std::size_t>(m_fenceFirst)].fence.signalled()) break;
        retireOldestFence(false);
    }
}

void GpuTilePool::endFrame() {
    if (m_ringHead == m_ringFenced) {
        return;  // no uploads since the last fence
    }
    if (m_fenceCount == kMaxFences) {
        retireOldestFence(true);
        ++m_stats.ringStalls;
    }
    FencedUploads& fenced =
        m_fences[static_cast<std::size_t>((m_fenceFirst + m_fenceCount) % kMaxFences)];
    fenced.fence = gl::Fence::insert();
    fenced.ringEnd = m_ringHead;
    m_ringFenced = m_ringHead;
    ++m_fenceCount;
}

std::optional<std::string> GpuTilePool::checkInvariants() const {
    if (auto broken = m_freeList.checkInvariants()) {
        return "free list: " + *broken;
    }
    if (static_cast<int>(m_slots.size()) != m_freeList.usedCount()) {
        return std::to_string(m_slots.size()) + " patches mapped but " +
               std::to_string(m_freeList.usedCount()) + " layers in use";
    }
    std::vector<std::uint8_t>& seen = m_invariantScratch;  // sized by create(): no allocation
    std::fill(seen.begin(), seen.end(), std::uint8_t{0});
    for (const auto& [id, slot] : m_slots) {
        // Built only for a message: checks run every frame in the stress tool.
        const auto name = [&id = id] {
            return "patch L" + std::to_string(id.level) + " (" + std::to_string(id.x) + ", " +
                   std::to_string(id.y) + ")";
        };
        if (slot.layer < 0 || slot.layer >= capacity()) {
            return name() + " maps to layer " + std::to_string(slot.layer) + ", out of range";
        }
        if (!m_freeList.isAllocated(slot.layer)) {
            return name() + " maps to layer " + std::to_string(slot.layer) + ", which is free";
        }
        auto& mark = seen[static_cast<std::size_t>(slot.layer)];
        if (mark != 0) {
            return "layer " + std::to_string(slot.layer) + " is mapped to two patches";
        }
        mark = 1;
        if (!(m_layerPatch[static_cast<std::size_t>(slot.layer)] == id)) {
            return name() + " maps to layer " + std::to_string(slot.layer) +
                   ", which records another patch";
        }
        const bool pinned = m_pinned[static_cast<std::size_t>(slot.layer)] != 0;
        if (pinned == m_lru.contains(slot.layer)) {
            return name() + " holds layer " + std::to_string(slot.layer) +
                   (pinned ? ", which is pinned but in the LRU order"
                           : ", which is missing from the LRU order");
        }
    }
    if (m_lru.size() + m_pinnedCount != m_freeList.usedCount()) {
        return std::to_string(m_lru.size()) + " layers in the LRU order and " +
               std::to_string(m_pinnedCount) + " pinned but " +
               std::to_string(m_freeList.usedCount()) + " in use";
    }
    if (m_fenceCount < 0 || m_fenceCount > kMaxFences || m_ringTail > m_ringFenced ||
        m_ringFenced > m_ringHead || m_ringHead - m_ringTail > m_ring.sizeBytes()) {
        return "upload ring positions inconsistent";
    }
    return std::nullopt;
}

}  // namespace terrain::cache
