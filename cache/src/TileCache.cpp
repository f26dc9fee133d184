// TileCache: a hash map of id → position in a std::list kept in LRU order; hits splice
// their node to the front, so no operation copies or reallocates a record.
#include "terrain/cache/TileCache.h"

#include "terrain/io/Assert.h"

#include <iterator>
#include <utility>

namespace terrain::cache {

std::size_t TileCache::recordBytes(const io::PatchRecord& record) {
    return record.heights.size() * sizeof(float) + record.valid.size() * sizeof(std::uint8_t) +
           record.blockErrors.size() * sizeof(io::BlockErrors) + kEntryOverheadBytes;
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
        removeEntry(found->second);
        replaced = true;
    }
    while (m_bytes + recordSize > m_budgetBytes) {
        evictLeastRecent();
    }
    const io::PatchId id = record.id;
    m_lru.push_front(Entry{std::move(record), recordSize});
    m_entries.emplace(id, m_lru.begin());
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
    removeEntry(found->second);
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
    removeEntry(std::prev(m_lru.end()));
    ++m_counters.evictions;
}

void TileCache::removeEntry(Lru::iterator it) {
    m_bytes -= it->bytes;
    m_entries.erase(it->record.id);
    recycle(std::move(it->record));
    m_lru.erase(it);
}

void TileCache::recycle(io::PatchRecord&& record) {
    if (m_recycled.size() < kMaxRecycledRecords) {
        m_recycled.push_back(std::move(record));
    }
}

}  // namespace terrain::cache
