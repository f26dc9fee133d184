#include "RowFill.h"

#include <algorithm>
#include <cmath>

namespace terrain::io::detail {

Result<std::int64_t> RowFill::fill(std::int64_t r, std::int64_t a, std::int64_t b,
                                   std::span<float> row, std::span<std::uint8_t> valid) {
    const std::int64_t width = m_reader.info().width;
    std::optional<RowNeighbour> west, east;
    if (a > 0 && std::isnan(row.front())) {
        auto found = nearestValid(r, a - 1, -1);
        if (!found) return found.error();
        if (found.value()) west = RowNeighbour{found.value()->first - a, found.value()->second};
    }
    if (b < width && std::isnan(row.back())) {
        auto found = nearestValid(r, b, +1);
        if (!found) return found.error();
        if (found.value()) east = RowNeighbour{found.value()->first - a, found.value()->second};
    }
    return fillNoDataWindow(row, valid, m_units, west, east);
}

Result<std::optional<std::pair<std::int64_t, float>>> RowFill::nearestValid(std::int64_t r,
                                                                            std::int64_t from,
                                                                            int direction) {
    const std::int64_t width = m_reader.info().width;
    std::int64_t chunk = 1024;
    for (std::int64_t x = from; x >= 0 && x < width;) {
        const std::int64_t x0 = direction < 0 ? std::max<std::int64_t>(0, x - chunk + 1) : x;
        const std::int64_t count = direction < 0 ? x - x0 + 1 : std::min(chunk, width - x);
        m_scratch.resize(static_cast<std::size_t>(count));
        if (auto read = m_reader.readWindow(x0, r, count, 1, m_scratch); !read) return read.error();
        for (std::int64_t k = 0; k < count; ++k) {
            const std::int64_t i = direction < 0 ? count - 1 - k : k;
            if (!std::isnan(m_scratch[static_cast<std::size_t>(i)]))
                return std::optional{std::pair{x0 + i, m_scratch[static_cast<std::size_t>(i)]}};
        }
        x = direction < 0 ? x0 - 1 : x + count;
        chunk = std::min<std::int64_t>(chunk * 2, std::int64_t{1} << 16);
    }
    return std::optional<std::pair<std::int64_t, float>>{};
}

}  // namespace terrain::io::detail
