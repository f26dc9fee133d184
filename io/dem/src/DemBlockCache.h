// A least-recently-used cache of decoded raster blocks (TIFF/EXR tiles, or groups of
// whole rows), already converted to metres. It lets a DEM reader serve windows that
// straddle block boundaries — the pyramid builder's 131-row bands over 256-row tiles —
// without decoding any block twice in a row.
#pragma once

#include <cstddef>
#include <cstdint>
#include <list>
#include <unordered_map>
#include <vector>

namespace terrain::io::detail {

class DemBlockCache {
public:
    explicit DemBlockCache(std::size_t capacityBytes) : m_capacityBytes(capacityBytes) {}

    /// The samples of block (bx, by), or nullptr; marks it most recently used. The
    /// pointer is valid until the next insert.
    const std::vector<float>* find(std::int64_t bx, std::int64_t by);

    /// Stores block (bx, by), then drops least recently used blocks beyond the capacity.
    void insert(std::int64_t bx, std::int64_t by, std::vector<float> samples);

    std::size_t sizeBytes() const { return m_sizeBytes; }

private:
    struct Entry {
        std::uint64_t key = 0;
        std::vector<float> samples;
    };
    static std::uint64_t keyOf(std::int64_t bx, std::int64_t by) {
        return (static_cast<std::uint64_t>(by) << 32U) | static_cast<std::uint32_t>(bx);
    }

    std::size_t m_capacityBytes = 0;
    std::size_t m_sizeBytes = 0;
    std::list<Entry> m_entries;  // most recently used first
    std::unordered_map<std::uint64_t, std::list<Entry>::iterator> m_index;
};

}  // namespace terrain::io::detail
