// LayerLru: the order in which the GPU tile pool's allocated layers were last used by a
// frame, so the pool can evict the layer the view has not needed for longest
// (DESIGN.md, "Streaming and caches": eviction of patches the current view does not need).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

namespace terrain::cache {

/// An intrusive doubly linked list over layer indices [0, capacity): O(1) insert, touch,
/// remove and least-recent lookup, no allocation after construction. Not thread-safe.
class LayerLru {
public:
    explicit LayerLru(int capacity = 0);

    /// Links a layer that is not in the list as the most recently used, in `frame`.
    void insert(int layer, std::uint64_t frame);
    /// Marks a listed layer used in `frame` (frames never go backwards for one layer).
    void touch(int layer, std::uint64_t frame);
    /// Unlinks a listed layer.
    void remove(int layer);

    bool contains(int layer) const;
    /// The least recently used layer, or nullopt when the list is empty.
    std::optional<int> leastRecent() const;
    /// The frame `layer` was last used in; layer must be listed.
    std::uint64_t lastUsedFrame(int layer) const;
    int size() const { return m_size; }

private:
    static constexpr int kNone = -1;
    std::vector<int> m_prev;  // towards the most recent end
    std::vector<int> m_next;  // towards the least recent end
    std::vector<std::uint64_t> m_frame;
    std::vector<std::uint8_t> m_listed;
    int m_mostRecent = kNone;
    int m_leastRecent = kNone;
    int m_size = 0;
};

}  // namespace terrain::cache
