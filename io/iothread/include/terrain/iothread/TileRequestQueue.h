// TileRequestQueue: the pending tile requests of the streaming I/O thread, highest priority
// first (the LOD tree's screen-space error), ties first come first served. A request is keyed
// by TileKey: the heights' patch or an imagery layer's tile, in one order (issue 47).
// Single-threaded: IoThread wraps it in its mutex.
#pragma once

#include "terrain/iothread/TileKey.h"
#include "terrain/pyramid/PyramidLayout.h"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <set>
#include <unordered_map>
#include <vector>

namespace terrain::io {

/// Not thread-safe: one thread at a time (the owner serialises calls).
/// Every operation is O(log n) in the number of pending requests.
///
/// Allocation: once size() has reached its high-water mark, request() (new or
/// re-prioritised), cancel(), popHighest() and clear() allocate nothing. A request that
/// leaves parks its set node and map node (node handles) for the next new request, a
/// re-prioritised one is re-keyed in its own node, and the map never holds more than the
/// high-water count, so it never rehashes after that. The nodes of the high-water count
/// stay allocated until the queue is destroyed.
class TileRequestQueue {
public:
    struct Request {
        PatchId id;
        float priority = 0.0f;  ///< higher is served first
        int imageryLayer = TileKey::kHeights;
        TileKey key() const { return {id, imageryLayer}; }
        bool operator==(const Request&) const = default;
    };

    /// Adds a request, or changes the priority of the pending request for `key` (a PatchId
    /// alone is the heights'). A re-prioritised request keeps its place among equal
    /// priorities (its first arrival). Returns true when the request is new. `priority` must
    /// not be NaN.
    bool request(const TileKey& key, float priority);

    /// Removes the pending request for `key`; false when there is none.
    bool cancel(const TileKey& key);

    /// Removes and returns the highest-priority request (the earliest among equals).
    std::optional<Request> popHighest();

    /// Priority of the pending request for `key`, if any.
    std::optional<float> priority(const TileKey& key) const;

    bool contains(const TileKey& key) const { return m_byId.contains(key); }
    std::size_t size() const { return m_byId.size(); }
    bool empty() const { return m_byId.empty(); }
    /// Removes every request, keeping their nodes for reuse.
    void clear();

private:
    struct Entry {
        float priority;
        std::uint64_t sequence;  // arrival order: breaks ties first come first served
        TileKey key;
    };
    struct EntryOrder {
        bool operator()(const Entry& a, const Entry& b) const {
            if (a.priority != b.priority) return a.priority > b.priority;
            return a.sequence < b.sequence;
        }
    };
    using Order = std::set<Entry, EntryOrder>;
    using IdMap = std::unordered_map<TileKey, Order::iterator, TileKeyHash>;

    void park(Order::iterator entry, IdMap::iterator byId);

    Order m_order;
    IdMap m_byId;
    // Nodes of requests that left, for the next new ones; always equally many of each. The
    // capacities cover every node ever allocated, so parking never grows them.
    std::vector<Order::node_type> m_spareEntries;
    std::vector<IdMap::node_type> m_spareIds;
    std::uint64_t m_nextSequence = 0;
};

}  // namespace terrain::io
