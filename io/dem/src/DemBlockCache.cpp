// LRU block cache (see DemBlockCache.h).
#include "DemBlockCache.h"

namespace terrain::io::detail {

const std::vector<float>* DemBlockCache::find(std::int64_t bx, std::int64_t by) {
    const auto it = m_index.find(keyOf(bx, by));
    if (it == m_index.end()) return nullptr;
    m_entries.splice(m_entries.begin(), m_entries, it->second);
    return &it->second->samples;
}

void DemBlockCache::insert(std::int64_t bx, std::int64_t by, std::vector<float> samples) {
    const std::uint64_t key = keyOf(bx, by);
    if (const auto it = m_index.find(key); it != m_index.end()) {
        m_sizeBytes -= it->second->samples.size() * sizeof(float);
        m_entries.erase(it->second);
        m_index.erase(it);
    }
    m_sizeBytes += samples.size() * sizeof(float);
    m_entries.push_front(Entry{key, std::move(samples)});
    m_index.emplace(key, m_entries.begin());
    // Keep at least the block just stored, whatever the capacity.
    while (m_sizeBytes > m_capacityBytes && m_entries.size() > 1) {
        const Entry& last = m_entries.back();
        m_sizeBytes -= last.samples.size() * sizeof(float);
        m_index.erase(last.key);
        m_entries.pop_back();
    }
}

}  // namespace terrain::io::detail
