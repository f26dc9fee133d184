// ImageryTileCache: the CPU cache of decoded imagery tiles (issue 47) between the I/O thread
// and the GPU imagery pool, under its own byte budget with least-recently-used eviction, as
// TileCache is for the heights. Tiles are keyed by (imagery layer, patch): io::TileKey.
// Absent tiles (info.present = false, no texels) are kept too, cheaply: they answer which
// tiles a layer lacks without asking the disk again.
#pragma once

#include "terrain/cache/TileCache.h"
#include "terrain/iothread/TileKey.h"
#include "terrain/pyramid/ImageryTile.h"

#include <cstddef>
#include <list>
#include <optional>
#include <unordered_map>
#include <vector>

namespace terrain::cache {

/// Render thread only: no locking. O(1) operations (amortised for the hash map).
///
/// Allocation, as TileCache: once entryCount() has reached its high-water mark, insert(),
/// find(), erase() and takeEvicted() allocate nothing (the tile's texels are the caller's);
/// entries that leave park their list and map nodes for the next insert. Tiles that leave
/// are kept, up to kMaxRecycledTiles, for takeEvicted(), so the I/O thread reads into their
/// storage; their bytes do not count.
class ImageryTileCache {
public:
    /// Bookkeeping charged per entry on top of its texels (an estimate).
    static constexpr std::size_t kEntryOverheadBytes = sizeof(io::ImageryTile) + 64;
    static constexpr std::size_t kMaxRecycledTiles = 4;

    /// Bytes an entry of `tile` is charged: the capacity of its texels and mips (what it
    /// holds, though an absent tile has neither) plus kEntryOverheadBytes.
    static std::size_t tileBytes(const io::ImageryTile& tile) {
        return tile.rgba.capacity() + tile.mips.capacity() + kEntryOverheadBytes;
    }
    /// What a present tile is charged: a budget below it holds no imagery.
    static constexpr std::size_t kPresentTileBytes =
        io::kImageryTileBytes + io::kImageryMipChainBytes + kEntryOverheadBytes;

    explicit ImageryTileCache(std::size_t budgetBytes);

    /// Stores `tile` of imagery layer `layer` (key {tile.id, layer}) as the most recently
    /// used entry, replacing one with the same key, evicting least recently used entries
    /// until it fits. TooLarge, leaving `tile` unmoved, when it alone exceeds the budget.
    TileCacheInsertResult insert(int layer, io::ImageryTile&& tile);

    /// The cached tile, or null; counts a hit or a miss and makes a hit the most recent.
    /// Valid until the next non-const call.
    const io::ImageryTile* find(const io::TileKey& key);
    /// The cached tile, or null, touching neither the order nor the counters.
    const io::ImageryTile* peek(const io::TileKey& key) const {
        const auto found = m_entries.find(key);
        return found == m_entries.end() ? nullptr : &found->second->tile;
    }
    bool contains(const io::TileKey& key) const { return m_entries.contains(key); }
    /// Drops an entry (not an eviction); false when it was not cached.
    bool erase(const io::TileKey& key);

    std::size_t bytes() const { return m_bytes; }
    std::size_t budgetBytes() const { return m_budgetBytes; }
    std::size_t entryCount() const { return m_entries.size(); }
    const TileCacheCounters& counters() const { return m_counters; }
    void resetCounters() { m_counters = {}; }

    /// A tile that left the cache, for reuse of its storage, or nullopt.
    std::optional<io::ImageryTile> takeEvicted();

private:
    struct Entry {
        io::TileKey key;
        io::ImageryTile tile;
        std::size_t bytes = 0;
    };
    using Lru = std::list<Entry>;  // front: most recently used
    using EntryMap = std::unordered_map<io::TileKey, Lru::iterator, io::TileKeyHash>;

    void evictLeastRecent();
    void removeEntry(EntryMap::iterator found);

    std::size_t m_budgetBytes = 0;
    std::size_t m_bytes = 0;
    Lru m_lru;
    EntryMap m_entries;
    Lru m_spareLruNodes;  // tiles moved out: they own no storage
    std::vector<EntryMap::node_type> m_spareMapNodes;
    std::vector<io::ImageryTile> m_recycled;  // reserved to kMaxRecycledTiles
    TileCacheCounters m_counters;
};

}  // namespace terrain::cache
