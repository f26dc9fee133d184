// The decoded heights of the last patches a reader read that have children. A patch whose
// heights are predicted from its parent's (HeightCodes.h, HeightPrediction) is decoded from
// them, and a streaming reader reads a parent before its children (the quadtree splits only
// into children of a resident patch), so the parent is usually still here; a miss costs a
// read of the parent, and perhaps of its own parent.
#pragma once

#include "terrain/pyramid/PyramidLayout.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace terrain::io {

class ParentTileCache {
public:
    /// Keeps at most `maxBytes` of heights, and always at least one tile of `tileSamples`².
    ParentTileCache(std::size_t maxBytes, int tileSamples)
        : m_maxTiles(std::max<std::size_t>(
              1, maxBytes / (sizeof(float) * static_cast<std::size_t>(tileSamples) *
                             static_cast<std::size_t>(tileSamples)))) {}

    /// The patch's heights, or null. Valid until the next insert.
    const std::vector<float>* find(const PatchId& id) {
        for (Entry& e : m_entries)
            if (e.id == id) {
                e.lastUse = ++m_clock;
                return &e.heights;
            }
        return nullptr;
    }

    /// Keeps `heights` as the patch's, in place of the least recently used when full.
    void insert(const PatchId& id, std::span<const float> heights) {
        Entry* slot = nullptr;
        if (m_entries.size() < m_maxTiles) {
            slot = &m_entries.emplace_back();
        } else {
            slot = &*std::min_element(
                m_entries.begin(), m_entries.end(),
                [](const Entry& a, const Entry& b) { return a.lastUse < b.lastUse; });
        }
        slot->id = id;
        slot->heights.assign(heights.begin(), heights.end());
        slot->lastUse = ++m_clock;
    }

private:
    struct Entry {
        PatchId id;
        std::vector<float> heights;
        std::uint64_t lastUse = 0;
    };
    std::size_t m_maxTiles;
    std::vector<Entry> m_entries;
    std::uint64_t m_clock = 0;
};

}  // namespace terrain::io
