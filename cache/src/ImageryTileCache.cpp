// ImageryTileCache: TileCache's scheme (a hash map into a std::list in LRU order, parked
// nodes reused) over imagery tiles.
#include "terrain/cache/ImageryTileCache.h"

#include "terrain/base/Assert.h"

#include <algorithm>
#include <utility>

namespace terrain::cache {

ImageryTileCache::ImageryTileCache(std::size_t budgetBytes) : m_budgetBytes(budgetBytes) {
    m_recycled.reserve(kMaxRecycledTiles);
}

TileCacheInsertResult ImageryTileCache::insert(int layer, io::ImageryTile&& tile) {
    TERRAIN_ASSERT(layer >= 0, "ImageryTileCache: an imagery layer is ≥ 0");
    const std::size_t size = tileBytes(tile);
    if (size > m_budgetBytes) return TileCacheInsertResult::TooLarge;
    const io::TileKey key{tile.id, layer};
    bool replaced = false;
    if (const auto found = m_entries.find(key); found != m_entries.end()) {
        removeEntry(found);
        replaced = true;
    }
    while (m_bytes + size > m_budgetBytes) evictLeastRecent();
    if (m_spareLruNodes.empty()) {
        // A new high-water entry count: the only time the cache allocates or rehashes.
        m_lru.push_front(Entry{key, std::move(tile), size});
        m_entries.emplace(key, m_lru.begin());
        const std::size_t nodeCount = m_entries.size();
        if (m_spareMapNodes.capacity() < nodeCount)
            m_spareMapNodes.reserve(std::max(nodeCount, 2 * m_spareMapNodes.capacity()));
    } else {
        m_lru.splice(m_lru.begin(), m_spareLruNodes, m_spareLruNodes.begin());
        m_lru.front().key = key;
        m_lru.front().tile = std::move(tile);
        m_lru.front().bytes = size;
        EntryMap::node_type node = std::move(m_spareMapNodes.back());
        m_spareMapNodes.pop_back();
        node.key() = key;
        node.mapped() = m_lru.begin();
        m_entries.insert(std::move(node));
    }
    m_bytes += size;
    ++m_counters.insertions;
    return replaced ? TileCacheInsertResult::Replaced : TileCacheInsertResult::Inserted;
}

const io::ImageryTile* ImageryTileCache::find(const io::TileKey& key) {
    const auto found = m_entries.find(key);
    if (found == m_entries.end()) {
        ++m_counters.misses;
        return nullptr;
    }
    ++m_counters.hits;
    m_lru.splice(m_lru.begin(), m_lru, found->second);
    return &found->second->tile;
}

bool ImageryTileCache::erase(const io::TileKey& key) {
    const auto found = m_entries.find(key);
    if (found == m_entries.end()) return false;
    removeEntry(found);
    return true;
}

std::optional<io::ImageryTile> ImageryTileCache::takeEvicted() {
    if (m_recycled.empty()) return std::nullopt;
    std::optional<io::ImageryTile> tile{std::move(m_recycled.back())};
    m_recycled.pop_back();
    return tile;
}

void ImageryTileCache::evictLeastRecent() {
    TERRAIN_ASSERT(!m_lru.empty(), "evicting from an empty imagery cache");
    const auto found = m_entries.find(m_lru.back().key);
    TERRAIN_ASSERT(found != m_entries.end(), "imagery cache LRU entry missing from its map");
    removeEntry(found);
    ++m_counters.evictions;
}

void ImageryTileCache::removeEntry(EntryMap::iterator found) {
    const Lru::iterator it = found->second;
    m_bytes -= it->bytes;
    m_spareMapNodes.push_back(m_entries.extract(found));  // within capacity: see insert()
    if (m_recycled.size() < kMaxRecycledTiles &&
        it->tile.rgba.capacity() + it->tile.mips.capacity() > 0)
        m_recycled.push_back(std::move(it->tile));
    it->tile = io::ImageryTile{};  // a parked node keeps no texel storage alive
    m_spareLruNodes.splice(m_spareLruNodes.begin(), m_lru, it);
}

}  // namespace terrain::cache
