// TileCache: the CPU cache of decoded patches between the I/O thread and the GPU tile pool,
// bounded by a byte budget with least-recently-used eviction (DESIGN.md, "Streaming and
// caches").
#pragma once

#include "terrain/pyramid/PatchIdHash.h"
#include "terrain/pyramid/PatchRecord.h"

#include <cstddef>
#include <cstdint>
#include <list>
#include <optional>
#include <unordered_map>
#include <vector>

namespace terrain::cache {

/// Per-frame telemetry; reset with TileCache::resetCounters().
struct TileCacheCounters {
    std::uint64_t hits = 0;        ///< find() calls that found their patch
    std::uint64_t misses = 0;      ///< find() calls that did not
    std::uint64_t evictions = 0;   ///< entries dropped to meet the budget (not erase())
    std::uint64_t insertions = 0;  ///< records stored by insert(), replacements included
    bool operator==(const TileCacheCounters&) const = default;
};

enum class TileCacheInsertResult {
    Inserted,  ///< stored as a new entry
    Replaced,  ///< stored in place of an entry with the same id
    TooLarge,  ///< not kept: the record alone exceeds the budget; the cache is unchanged
};

/// Maps io::PatchId to a decoded io::PatchRecord within budgetBytes(), evicting the least
/// recently used entries. All operations are O(1) (amortised for the hash map).
///
/// Render thread only: there is no locking. The I/O thread hands records over through its
/// completion queue; the render thread inserts them here.
///
/// Records that leave the cache (evicted, erased, replaced) are kept, up to
/// kMaxRecycledRecords, for takeEvicted(), so the I/O thread can decode into their
/// vectors instead of allocating new ones. Their bytes do not count towards the budget.
///
/// Allocation: once entryCount() has reached its high-water mark, insert(), find(),
/// erase(), setBudgetBytes() and takeEvicted() allocate nothing (the vectors a record
/// brings with it are the caller's). The bookkeeping of an entry that leaves (its LRU list
/// node and hash-map node) is kept and reused by the next insert, and the hash map never
/// holds more than the high-water count, so it never rehashes after that. The cost is the
/// memory of the high-water count of nodes, released only with the cache.
class TileCache {
public:
    /// Bookkeeping charged per entry on top of its vectors: the record struct, the LRU
    /// list node and the hash-map node and bucket. An estimate, so that many tiny records
    /// cannot grow the cache without bound.
    static constexpr std::size_t kEntryOverheadBytes = sizeof(io::PatchRecord) + 64;
    /// Records kept for takeEvicted(); small, as the I/O thread has few requests in flight.
    static constexpr std::size_t kMaxRecycledRecords = 4;

    /// Bytes an entry is charged: the sizes (not capacities) of its vectors in bytes plus
    /// kEntryOverheadBytes.
    static std::size_t recordBytes(const io::PatchRecord& record);
    /// What recordBytes() charges a patch of `layout` (with its no-data mask when
    /// `withMask`): a budget below it holds no tile at all.
    static std::size_t tileBytes(const io::PyramidLayout& layout, bool withMask);

    explicit TileCache(std::size_t budgetBytes);

    /// Stores `record` as the most recently used entry, first dropping an entry with the
    /// same id, then evicting least-recently-used entries until it fits. A record larger
    /// than the whole budget is not kept (TooLarge): nothing is evicted for it and
    /// `record` is left unmoved, so the caller may recycle it.
    /// Render thread only.
    TileCacheInsertResult insert(io::PatchRecord&& record);

    /// The cached record, or null. Counts a hit or a miss; a hit makes the entry the most
    /// recently used. The pointer is valid until the next non-const call. Render thread only.
    const io::PatchRecord* find(const io::PatchId& id);

    /// Whether `id` is cached; touches neither the LRU order nor the counters.
    bool contains(const io::PatchId& id) const { return m_entries.contains(id); }

    /// The cached record, or null, touching neither the LRU order nor the counters (a look
    /// that must not keep a record alive, e.g. the viewer's ground under the camera). The
    /// pointer is valid until the next non-const call. Render thread only.
    const io::PatchRecord* peek(const io::PatchId& id) const {
        const auto found = m_entries.find(id);
        return found == m_entries.end() ? nullptr : &found->second->record;
    }

    /// Drops `id`'s entry (not counted as an eviction); false when it was not cached.
    /// Render thread only.
    bool erase(const io::PatchId& id);

    /// Evicts least-recently-used entries until bytes() ≤ budgetBytes. Render thread only.
    void setBudgetBytes(std::size_t budgetBytes);

    std::size_t bytes() const { return m_bytes; }
    std::size_t budgetBytes() const { return m_budgetBytes; }
    std::size_t entryCount() const { return m_entries.size(); }

    /// Least recently used first; O(n), for tests and debug overlays.
    std::vector<io::PatchId> idsLeastRecentFirst() const;

    const TileCacheCounters& counters() const { return m_counters; }
    void resetCounters() { m_counters = {}; }

    /// One record that left the cache, for reuse of its vectors (contents are stale), or
    /// nullopt when none is kept. Render thread only.
    std::optional<io::PatchRecord> takeEvicted();
    std::size_t recycledCount() const { return m_recycled.size(); }

private:
    struct Entry {
        io::PatchRecord record;
        std::size_t bytes = 0;
    };
    using Lru = std::list<Entry>;  // front: most recently used
    using EntryMap = std::unordered_map<io::PatchId, Lru::iterator, io::PatchIdHash>;

    void evictLeastRecent();
    void removeEntry(EntryMap::iterator found);  // unlinks it, recycling its record and nodes
    void recycle(io::PatchRecord&& record);

    std::size_t m_budgetBytes = 0;
    std::size_t m_bytes = 0;
    Lru m_lru;
    EntryMap m_entries;
    // Nodes of entries that left, for the next inserts. Always equally many of each: an
    // entry owns one of both. m_spareMapNodes' capacity covers every node ever allocated,
    // so parking a node never grows it.
    Lru m_spareLruNodes;  // records moved out: they own no storage
    std::vector<EntryMap::node_type> m_spareMapNodes;
    std::vector<io::PatchRecord> m_recycled;  // reserved to kMaxRecycledRecords
    TileCacheCounters m_counters;
};

}  // namespace terrain::cache
