// LayerFreeList: which layers of the GPU tile pool's texture arrays are unused
// (Yusov & Shevtsov 2011, §5 "Implementation Details": "a list of unused subresources").
// CPU only; the pool owns one and maps allocated layers to resident patches.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace terrain::cache {

/// A fixed set of layers [0, capacity). allocate() and release() are O(1) and never
/// allocate memory after construction, so the pool stays allocation-free in steady state.
/// Not thread-safe: the pool lives on the render thread.
class LayerFreeList {
public:
    /// All `capacity` layers start free; allocate() hands them out from layer 0 upwards.
    /// capacity ≥ 0 (TERRAIN_ASSERT).
    explicit LayerFreeList(int capacity);

    /// An unused layer, now marked in use; nullopt when every layer is in use.
    std::optional<int> allocate();

    /// Returns an allocated layer to the free list. Releasing a layer that is out of range
    /// or already free is a programmer error (TERRAIN_ASSERT).
    void release(int layer);

    /// False for free layers; out-of-range layers are a programmer error (TERRAIN_ASSERT).
    bool isAllocated(int layer) const;

    int freeCount() const { return m_freeCount; }
    int usedCount() const { return capacity() - m_freeCount; }
    int capacity() const { return static_cast<int>(m_allocated.size()); }

    /// The first broken invariant, described, or nullopt: every free-stack entry in range,
    /// marked free and listed once; every layer either free or in use, never both or
    /// neither; free + used = capacity. O(capacity): for tests and the stress tool.
    std::optional<std::string> checkInvariants() const;

private:
    // m_freeStack[0, m_freeCount) lists the free layers; the top is handed out next.
    // The stack has room for every layer, so release() never grows it.
    std::vector<int> m_freeStack;
    std::vector<std::uint8_t> m_allocated;  // per layer: 1 in use, 0 free
    int m_freeCount = 0;
};

}  // namespace terrain::cache
