// ParentTileCache: the decoded heights of patches that have children, kept for their
// children. A patch whose heights are predicted from its parent's (HeightCodes.h,
// HeightPrediction) is decoded from them; a miss costs a read of the parent, and perhaps of
// its own parent. The streaming reads a parent before its children (the quadtree splits only
// into children of a resident patch), so a small cache serves it; a reader asked for patches
// in a shuffled order misses far more, and several reader threads sharing one cache (one per
// IoThread) keep each other's parents (docs/pyramid-format.md, "Reader threads").
#pragma once

#include "terrain/pyramid/PatchIdHash.h"
#include "terrain/pyramid/PyramidLayout.h"

#include <cstddef>
#include <list>
#include <memory>
#include <mutex>
#include <span>
#include <unordered_map>
#include <utility>
#include <vector>

namespace terrain::io {

/// Thread-safe: readers on several threads may share one. Least recently used tiles go
/// first once it holds its byte budget.
class ParentTileCache {
public:
    using Heights = std::shared_ptr<const std::vector<float>>;

    /// Keeps at most `maxBytes` of heights, and always the last tile inserted.
    explicit ParentTileCache(std::size_t maxBytes) : m_maxBytes(maxBytes) {}

    /// The patch's heights, or null. They stay valid while held, whatever is evicted.
    Heights find(const PatchId& id) {
        std::lock_guard lock(m_mutex);
        const auto it = m_index.find(id);
        if (it == m_index.end()) return nullptr;
        m_lru.splice(m_lru.begin(), m_lru, it->second);  // now the most recently used
        return it->second->second;
    }

    /// Keeps a copy of `heights` as the patch's, evicting the least recently used beyond the
    /// budget; returns what it keeps (the copy already kept, if another thread read it too).
    Heights insert(const PatchId& id, std::span<const float> heights) {
        // The copy is made outside the lock: other readers only wait for the list's update.
        auto kept = std::make_shared<const std::vector<float>>(heights.begin(), heights.end());
        std::lock_guard lock(m_mutex);
        if (const auto it = m_index.find(id); it != m_index.end()) {
            m_lru.splice(m_lru.begin(), m_lru, it->second);  // another thread read it too
            return it->second->second;
        }
        m_lru.emplace_front(id, kept);
        m_index.emplace(id, m_lru.begin());
        m_bytes += bytesOf(*kept);
        while (m_bytes > m_maxBytes && m_lru.size() > 1) {
            m_bytes -= bytesOf(*m_lru.back().second);
            m_index.erase(m_lru.back().first);
            m_lru.pop_back();
        }
        return kept;
    }

private:
    using Entry = std::pair<PatchId, Heights>;
    static std::size_t bytesOf(const std::vector<float>& heights) {
        return heights.size() * sizeof(float);
    }
    const std::size_t m_maxBytes;
    std::size_t m_bytes = 0;  // of the heights in m_lru
    std::mutex m_mutex;
    std::list<Entry> m_lru;  // most recently used first
    std::unordered_map<PatchId, std::list<Entry>::iterator, PatchIdHash> m_index;
};

}  // namespace terrain::io
