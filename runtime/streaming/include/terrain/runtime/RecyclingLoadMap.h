// RecyclingLoadMap: the streamers' map of the loads under way, keyed by tile, whose erased
// nodes are kept and reused for the next insertions, so that once reserve() has covered the
// busiest frames a steady stream of requests allocates nothing (TileStreamer, ImageryStreamer).
#pragma once

#include <cstddef>
#include <iterator>
#include <unordered_map>
#include <utility>
#include <vector>

namespace terrain::runtime {

/// An unordered_map whose erase() parks the node instead of freeing it. Not thread-safe
/// (the streamers use it on the render thread).
template <class Key, class Value, class Hash>
class RecyclingLoadMap {
    using Map = std::unordered_map<Key, Value, Hash>;

public:
    using iterator = typename Map::iterator;
    using const_iterator = typename Map::const_iterator;

    /// Room for `count` loads (buckets and parked nodes) without allocating.
    void reserve(std::size_t count) {
        m_map.reserve(count);
        m_spareNodes.reserve(count);
    }

    /// The value of `key`; when absent, inserted as `makeFresh()` (called only then) in a
    /// parked node if there is one.
    template <class MakeFresh>
    Value& findOrInsert(const Key& key, MakeFresh&& makeFresh) {
        if (const auto found = m_map.find(key); found != m_map.end()) return found->second;
        if (!m_spareNodes.empty()) {
            typename Map::node_type node = std::move(m_spareNodes.back());
            m_spareNodes.pop_back();
            node.key() = key;
            node.mapped() = std::forward<MakeFresh>(makeFresh)();
            return m_map.insert(std::move(node)).position->second;
        }
        return m_map.emplace(key, std::forward<MakeFresh>(makeFresh)()).first->second;
    }

    /// Removes the load at `it`, parking its node; returns the iterator after it (the others
    /// stay valid).
    iterator erase(iterator it) {
        const iterator next = std::next(it);
        m_spareNodes.push_back(m_map.extract(it));
        return next;
    }

    iterator find(const Key& key) { return m_map.find(key); }
    const_iterator find(const Key& key) const { return m_map.find(key); }
    iterator begin() { return m_map.begin(); }
    iterator end() { return m_map.end(); }
    const_iterator begin() const { return m_map.begin(); }
    const_iterator end() const { return m_map.end(); }
    std::size_t size() const { return m_map.size(); }

private:
    Map m_map;
    std::vector<typename Map::node_type> m_spareNodes;
};

}  // namespace terrain::runtime
