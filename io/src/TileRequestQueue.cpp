// TileRequestQueue: an ordered set of (priority desc, arrival) plus an id → entry index.
#include "terrain/io/TileRequestQueue.h"

#include "terrain/io/Assert.h"

#include <cmath>

namespace terrain::io {

bool TileRequestQueue::request(const PatchId& id, float priority) {
    TERRAIN_ASSERT(!std::isnan(priority), "TileRequestQueue: NaN priority");
    if (const auto found = m_byId.find(id); found != m_byId.end()) {
        const std::uint64_t sequence = found->second->sequence;
        m_order.erase(found->second);
        found->second = m_order.insert(Entry{priority, sequence, id}).first;
        return false;
    }
    const auto inserted = m_order.insert(Entry{priority, m_nextSequence++, id}).first;
    m_byId.emplace(id, inserted);
    return true;
}

bool TileRequestQueue::cancel(const PatchId& id) {
    const auto found = m_byId.find(id);
    if (found == m_byId.end()) return false;
    m_order.erase(found->second);
    m_byId.erase(found);
    return true;
}

std::optional<TileRequestQueue::Request> TileRequestQueue::popHighest() {
    if (m_order.empty()) return std::nullopt;
    const Entry top = *m_order.begin();
    m_order.erase(m_order.begin());
    m_byId.erase(top.id);
    return Request{top.id, top.priority};
}

std::optional<float> TileRequestQueue::priority(const PatchId& id) const {
    const auto found = m_byId.find(id);
    if (found == m_byId.end()) return std::nullopt;
    return found->second->priority;
}

void TileRequestQueue::clear() {
    m_order.clear();
    m_byId.clear();
}

}  // namespace terrain::io
