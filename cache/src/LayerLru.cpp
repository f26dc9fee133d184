// LayerLru: prev/next arrays indexed by layer; the head is the most recently used.
#include "terrain/cache/LayerLru.h"

#include "terrain/base/Assert.h"

#include <cstddef>

namespace terrain::cache {
namespace {
std::size_t at(int layer) { return static_cast<std::size_t>(layer); }
}  // namespace

LayerLru::LayerLru(int capacity)
    : m_prev(at(capacity), kNone),
      m_next(at(capacity), kNone),
      m_frame(at(capacity), 0),
      m_listed(at(capacity), 0) {}

bool LayerLru::contains(int layer) const {
    TERRAIN_ASSERT(layer >= 0 && at(layer) < m_listed.size(), "LayerLru: layer out of range");
    return m_listed[at(layer)] != 0;
}

void LayerLru::insert(int layer, std::uint64_t frame) {
    TERRAIN_ASSERT(!contains(layer), "LayerLru::insert of a listed layer");
    m_listed[at(layer)] = 1;
    m_frame[at(layer)] = frame;
    m_prev[at(layer)] = kNone;
    m_next[at(layer)] = m_mostRecent;
    if (m_mostRecent != kNone) m_prev[at(m_mostRecent)] = layer;
    m_mostRecent = layer;
    if (m_leastRecent == kNone) m_leastRecent = layer;
    ++m_size;
}

void LayerLru::remove(int layer) {
    TERRAIN_ASSERT(contains(layer), "LayerLru::remove of a layer that is not listed");
    const int prev = m_prev[at(layer)];
    const int next = m_next[at(layer)];
    if (prev != kNone) {
        m_next[at(prev)] = next;
    } else {
        m_mostRecent = next;
    }
    if (next != kNone) {
        m_prev[at(next)] = prev;
    } else {
        m_leastRecent = prev;
    }
    m_listed[at(layer)] = 0;
    m_prev[at(layer)] = kNone;
    m_next[at(layer)] = kNone;
    --m_size;
}

void LayerLru::touch(int layer, std::uint64_t frame) {
    TERRAIN_ASSERT(frame >= lastUsedFrame(layer), "LayerLru::touch: frames went backwards");
    if (m_mostRecent != layer) {
        remove(layer);
        insert(layer, frame);
    } else {
        m_frame[at(layer)] = frame;
    }
}

std::optional<int> LayerLru::leastRecent() const {
    if (m_leastRecent == kNone) return std::nullopt;
    return m_leastRecent;
}

std::uint64_t LayerLru::lastUsedFrame(int layer) const {
    TERRAIN_ASSERT(contains(layer), "LayerLru::lastUsedFrame of a layer that is not listed");
    return m_frame[at(layer)];
}

}  // namespace terrain::cache
