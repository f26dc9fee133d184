// TileRequestQueue: an ordered set of (priority desc, arrival) plus an id → entry index.
// Leaving requests park their nodes (node handles) for the next new request, and a
// re-prioritised request is re-keyed in place, so a warm queue allocates nothing.
#include "terrain/iothread/TileRequestQueue.h"

#include "terrain/base/Assert.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace terrain::io {

namespace {

// Grows `spares` geometrically to hold nodeCount parked nodes, so that parking any node
// there never allocates.
template <typename Node>
void reserveToPark(std::vector<Node>& spares, std::size_t nodeCount) {
    if (spares.capacity() < nodeCount) {
        spares.reserve(std::max(nodeCount, 2 * spares.capacity()));
    }
}

}  // namespace

bool TileRequestQueue::request(const TileKey& key, float priority) {
    TERRAIN_ASSERT(!std::isnan(priority), "TileRequestQueue: NaN priority");
    if (const auto found = m_byId.find(key); found != m_byId.end()) {
        // Re-keyed in its own node; the sequence (first arrival) stays.
        Order::node_type node = m_order.extract(found->second);
        node.value().priority = priority;
        found->second = m_order.insert(std::move(node)).position;
        return false;
    }
    const Entry entry{priority, m_nextSequence++, key};
    if (m_spareEntries.empty()) {
        // A new high-water count: the only time the queue allocates, and the only time the
        // map may rehash.
        const auto inserted = m_order.insert(entry).first;
        m_byId.emplace(key, inserted);
        reserveToPark(m_spareEntries, m_byId.size());  // nothing is parked now
        reserveToPark(m_spareIds, m_byId.size());
        return true;
    }
    Order::node_type entryNode = std::move(m_spareEntries.back());
    m_spareEntries.pop_back();
    entryNode.value() = entry;
    const auto inserted = m_order.insert(std::move(entryNode)).position;
    IdMap::node_type idNode = std::move(m_spareIds.back());
    m_spareIds.pop_back();
    idNode.key() = key;
    idNode.mapped() = inserted;
    m_byId.insert(std::move(idNode));
    return true;
}

bool TileRequestQueue::cancel(const TileKey& key) {
    const auto found = m_byId.find(key);
    if (found == m_byId.end()) return false;
    park(found->second, found);
    return true;
}

std::optional<TileRequestQueue::Request> TileRequestQueue::popHighest() {
    if (m_order.empty()) return std::nullopt;
    const auto top = m_order.begin();
    const Request popped{top->key.id, top->priority, top->key.imageryLayer};
    const auto found = m_byId.find(top->key);
    TERRAIN_ASSERT(found != m_byId.end(), "TileRequestQueue: entry missing from its index");
    park(top, found);
    return popped;
}

std::optional<float> TileRequestQueue::priority(const TileKey& key) const {
    const auto found = m_byId.find(key);
    if (found == m_byId.end()) return std::nullopt;
    return found->second->priority;
}

void TileRequestQueue::clear() {
    while (!m_byId.empty()) {
        const auto found = m_byId.begin();
        park(found->second, found);
    }
}

void TileRequestQueue::park(Order::iterator entry, IdMap::iterator byId) {
    m_spareEntries.push_back(m_order.extract(entry));  // within capacity: see request()
    m_spareIds.push_back(m_byId.extract(byId));
}

}  // namespace terrain::io
