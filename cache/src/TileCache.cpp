// TileCache: a hash map of id → position in a std::list kept in LRU order; hits splice
// their node to the front, so no operation copies or reallocates a record. Entries that
// leave park their list node and map node (a node handle) for the next insert, so a warm
// cache allocates nothing.
#include "terrain/cache/TileCache.h"

#include "terrain/base/Assert.h"

#include <algorithm>
#include <iterator>
#include <utility>

namespace terrain::cache {

std::size_t TileCache::recordBytes(const io::PatchRecord& record) {
    return record.heights.size() * sizeof(float) + record.valid.size() * sizeof(std::uint8_t) +
           record.blockErrors.size() * sizeof(io::BlockErrors) + kEntryOverheadBytes;
}

std::size_t TileCache::tileBytes(const io::PyramidLayout& layout, bool withMask) {
    const auto tile = static_cast<std::size_t>(layout.tileSamples());
    const auto blocks = static_cast<std::size_t>(layout.blocksPerSide());
    return tile * tile * (sizeof(float) + (withMask ? sizeof(std::uint8_t) : 0)) +
           blocks * blocks * sizeof(io::BlockErrors) + kEntryOverheadBytes;
}

TileCache::TileCache(std::size_t budgetBytes) : m_budgetBytes(budgetBytes) {
    m_recycled.reserve(kMaxRecycledRecords);
}

TileCacheInsertResult TileCache::insert(io::PatchRecord&& record) {
    const std::size_t recordSize = recordBytes(record);
    if (recordSize > m_budgetBytes) {
        return TileCacheInsertResult::TooLarge;
    }
    bool replaced = false;
    if (const auto found = m_entries.find(record.id); found != m_entries.end()) {
        removeEntry(found);
        replaced = true;
    }
    while (m_bytes + recordSize > m_budgetBytes) {
        evictLeastRecent();
    }
    const io::PatchId id = record.id;
    if (m_spareLruNodes.empty()) {
        // A new high-water entry count: the only time the cache allocates. The map may
        // rehash here, and only here: it never holds more entries than at this moment.
        m_lru.push_front(Entry{std::move(record), recordSize});
        m_entries.emplace(id, m_lru.begin());
        // Room to park every node there is (none is parked now), growing geometrically.
        const std::size_t nodeCount = m_entries.size();
        if (m_spareMapNodes.capacity() < nodeCount) {
            m_spareMapNodes.reserve(std::max(nodeCount, 2 * m_spareMapNodes.capacity()));
        }
    } else {
        m_lru.splice(m_lru.begin(), m_spareLruNodes, m_spareLruNodes.begin());
        m_lru.front().record = std::move(record);
        m_lru.front().bytes = recordSize;
        EntryMap::node_type node = std::move(m_spareMapNodes.back());
        m_spareMapNodes.pop_back();
        node.key() = id;
        node.mapped() = m_lru.begin();
        m_entries.insert(std::move(node));
    }
    m_bytes += recordSize;
    ++m_counters.insertions;
    return replaced ? TileCacheInsertResult::Replaced : TileCacheInsertResult::Inserted;
}

const io::PatchRecord* TileCache::find(const io::PatchId& id) {
    const auto found = m_entries.find(id);
    if (found == m_entries.end()) {
        ++m_counters.misses;
        return nullptr;
    }
    ++m_counters.hits;
    m_lru.splice(m_lru.begin(), m_lru, found->second);  // iterators stay valid
    return &found->second->record;
}

bool TileCache::erase(const io::PatchId& id) {
    const auto found = m_entries.find(id);
    if (found == m_entries.end()) {
        return false;
    }
    removeEntry(found);
    return true;
}

void TileCache::setBudgetBytes(std::size_t budgetBytes) {
    m_budgetBytes = budgetBytes;
    while (m_bytes > m_budgetBytes) {
        evictLeastRecent();
    }
}

std::vector<io::PatchId> TileCache::idsLeastRecentFirst() const {
    std::vector<io::PatchId> ids;
    ids.reserve(m_lru.size());
    for (auto it = m_lru.rbegin(); it != m_lru.rend(); ++it) {
        ids.push_back(it->record.id);
    }
    return ids;
}

std::optional<io::PatchRecord> TileCache::takeEvicted() {
    if (m_recycled.empty()) {
        return std::nullopt;
    }
    std::optional<io::PatchRecord> record{std::move(m_recycled.back())};
    m_recycled.pop_back();
    return record;
}

void TileCache::evictLeastRecent() {
    // Callers only evict while bytes exceed the budget, which needs at least one entry.
    TERRAIN_ASSERT(!m_lru.empty(), "evicting from an empty tile cache");
    const auto found = m_entries.find(m_lru.back().record.id);
    TERRAIN_ASSERT(found != m_entries.end(), "tile cache LRU entry missing from its map");
    removeEntry(found);
    ++m_counters.evictions;
}

void TileCache::removeEntry(EntryMap::iterator found) {
    const Lru::iterator it = found->second;
    m_bytes -= it->bytes;
    m_spareMapNodes.push_back(m_entries.extract(found));  // within capacity: see insert()
    recycle(std::move(it->record));
    it->record = io::PatchRecord{};  // a parked node keeps no vector storage alive
    m_spareLruNodes.splice(m_spareLruNodes.begin(), m_lru, it);
}

void TileCache::recycle(io::PatchRecord&& record) {
    if (m_recycled.size() < kMaxRecycledRecords) {
        m_recycled.push_back(std::move(record));
    }
}

}  // namespace terrain::cache
