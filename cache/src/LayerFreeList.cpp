// LayerFreeList: a stack of free layer indices plus a per-layer "in use" flag; the flag
// makes isAllocated() O(1) and catches double releases.
#include "terrain/cache/LayerFreeList.h"

#include "terrain/base/Assert.h"

#include <cstddef>

namespace terrain::cache {

LayerFreeList::LayerFreeList(int capacity) {
    TERRAIN_ASSERT(capacity >= 0, "layer capacity must not be negative");
    const auto count = static_cast<std::size_t>(capacity);
    m_freeStack.resize(count);
    m_allocated.assign(count, 0);
    // Highest layer at the bottom, so the first allocations return 0, 1, 2, ...
    for (std::size_t i = 0; i < count; ++i) {
        m_freeStack[i] = capacity - 1 - static_cast<int>(i);
    }
    m_freeCount = capacity;
}

std::optional<int> LayerFreeList::allocate() {
    if (m_freeCount == 0) {
        return std::nullopt;
    }
    --m_freeCount;
    const int layer = m_freeStack[static_cast<std::size_t>(m_freeCount)];
    m_allocated[static_cast<std::size_t>(layer)] = 1;
    return layer;
}

void LayerFreeList::release(int layer) {
    TERRAIN_ASSERT(layer >= 0 && layer < capacity(), "released layer out of range");
    TERRAIN_ASSERT(m_allocated[static_cast<std::size_t>(layer)] != 0,
                   "released a layer that is already free");
    m_allocated[static_cast<std::size_t>(layer)] = 0;
    m_freeStack[static_cast<std::size_t>(m_freeCount)] = layer;
    ++m_freeCount;
}

bool LayerFreeList::isAllocated(int layer) const {
    TERRAIN_ASSERT(layer >= 0 && layer < capacity(), "layer out of range");
    return m_allocated[static_cast<std::size_t>(layer)] != 0;
}

std::optional<std::string> LayerFreeList::checkInvariants() const {
    const int n = capacity();
    if (m_freeStack.size() != m_allocated.size()) {
        return "free stack has room for " + std::to_string(m_freeStack.size()) +
               " layers, capacity is " + std::to_string(n);
    }
    if (m_freeCount < 0 || m_freeCount > n) {
        return "free count " + std::to_string(m_freeCount) + " outside [0, " + std::to_string(n) +
               "]";
    }
    std::vector<std::uint8_t> listedFree(m_allocated.size(), 0);
    for (int i = 0; i < m_freeCount; ++i) {
        const int layer = m_freeStack[static_cast<std::size_t>(i)];
        if (layer < 0 || layer >= n) {
            return "free stack entry " + std::to_string(i) + " holds layer " +
                   std::to_string(layer) + ", outside [0, " + std::to_string(n) + ")";
        }
        const auto index = static_cast<std::size_t>(layer);
        if (listedFree[index] != 0) {
            return "layer " + std::to_string(layer) + " is listed free twice";
        }
        listedFree[index] = 1;
        if (m_allocated[index] != 0) {
            return "layer " + std::to_string(layer) + " is both free and in use";
        }
    }
    int usedFlags = 0;
    for (int layer = 0; layer < n; ++layer) {
        const auto index = static_cast<std::size_t>(layer);
        if (m_allocated[index] != 0) {
            ++usedFlags;
        } else if (listedFree[index] == 0) {
            return "layer " + std::to_string(layer) + " is neither free nor in use (leaked)";
        }
    }
    if (m_freeCount + usedFlags != n) {
        return "free " + std::to_string(m_freeCount) + " + used " + std::to_string(usedFlags) +
               " != capacity " + std::to_string(n);
    }
    return std::nullopt;
}

}  // namespace terrain::cache
