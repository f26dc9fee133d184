#include "GeographicBlocks.h"

#include <algorithm>

namespace terrain::io::detail {

Status readPoles(DemReader& reader, SourceVoids& voids, GeographicGrid& grid) {
    RowFill fill(voids);
    for (int side = 0; side < 2; ++side) {
        const std::optional<std::int64_t> row = grid.poleRow(side);
        if (!row) continue;
        std::vector<float> heights(static_cast<std::size_t>(grid.width()));
        std::vector<std::uint8_t> valid(heights.size());
        if (Status read = reader.readWindow(0, *row, grid.width(), 1, heights); !read)
            return read.error();
        if (Result<std::int64_t> filled = fill.fill(*row, 0, heights, valid); !filled)
            return filled.error();
        grid.setPole(side, heights, valid);
    }
    return {};
}

GeographicBlocks::GeographicBlocks(DemReader& reader, SourceVoids& voids,
                                   const GeographicGrid& grid, std::uint64_t cacheBytes,
                                   std::int64_t blockRows, std::int64_t blockColumns)
    // GeographicGrid::read fills with no rounding to the source's units: so does this.
    : m_reader(reader),
      m_grid(grid),
      m_blockRows(blockRows),
      m_blockColumns(blockColumns),
      m_fill(voids),
      m_capacity(std::max<std::size_t>(
          4, static_cast<std::size_t>(cacheBytes / std::uint64_t(blockRows * blockColumns * 5)))) {}

Result<const GeographicBlocks::Block*> GeographicBlocks::block(std::int64_t blockRow,
                                                               std::int64_t blockColumn) {
    const std::uint64_t key = (std::uint64_t(blockRow) << 32) | std::uint64_t(blockColumn);
    if (auto found = m_cache.find(key); found != m_cache.end()) {
        m_recent.splice(m_recent.begin(), m_recent, found->second.recent);
        return found->second.block.get();
    }
    auto b = std::make_unique<Block>();
    b->row0 = blockRow * m_blockRows;
    b->column0 = blockColumn * m_blockColumns;
    b->rows = std::min(m_blockRows, m_grid.height() - b->row0);
    b->columns = std::min(m_blockColumns, m_grid.width() - b->column0);
    const auto count = static_cast<std::size_t>(b->rows * b->columns);
    b->heights.resize(count);
    b->valid.resize(count);
    if (Status read = m_reader.readWindow(b->column0, b->row0, b->columns, b->rows, b->heights);
        !read)
        return read.error();
    for (std::int64_t r = 0; r < b->rows; ++r) {
        const auto offset = static_cast<std::size_t>(r * b->columns);
        std::span<float> row(b->heights.data() + offset, static_cast<std::size_t>(b->columns));
        std::span<std::uint8_t> valid(b->valid.data() + offset, row.size());
        Result<std::int64_t> filled = m_fill.fill(b->row0 + r, b->column0, row, valid);
        if (!filled) return filled.error();
    }
    ++m_blocksRead;
    if (m_cache.size() >= m_capacity) {
        m_cache.erase(m_recent.back());
        m_recent.pop_back();
    }
    m_recent.push_front(key);
    const Block* stored = b.get();
    m_cache.emplace(key, Cached{std::move(b), m_recent.begin()});
    return stored;
}

Result<GeographicGrid::Resampled> GeographicBlocks::at(double latitudeDeg, double longitudeDeg) {
    const std::optional<GeographicGrid::Location> where = m_grid.locate(latitudeDeg, longitudeDeg);
    if (!where) return GeographicGrid::Resampled{};
    float corner[2][2] = {};
    bool valid[2][2] = {};
    // Most points' four samples lie in one block: a corner in the previous corner's block
    // reuses it, so one lookup instead of four (a repeated lookup would only move the block
    // to the front of the recently used again, where it already is).
    const Block* previous = nullptr;
    for (int r = 0; r < 2; ++r) {
        for (int c = 0; c < 2; ++c) {
            const std::int64_t row = where->rows[r], column = where->columns[c];
            const std::int64_t blockRow = row / m_blockRows, blockColumn = column / m_blockColumns;
            if (previous == nullptr || previous->row0 != blockRow * m_blockRows ||
                previous->column0 != blockColumn * m_blockColumns) {
                Result<const Block*> b = block(blockRow, blockColumn);
                if (!b) return b.error();
                previous = b.value();
            }
            const auto i = static_cast<std::size_t>((row - previous->row0) * previous->columns +
                                                    (column - previous->column0));
            corner[r][c] = previous->heights[i];
            valid[r][c] = previous->valid[i] != 0;
        }
    }
    return GeographicGrid::interpolate(*where, corner, valid);
}

Status GeographicBlocks::forEachPiece(std::int64_t row0, std::int64_t row1, std::int64_t column0,
                                      std::int64_t column1,
                                      const std::function<void(const Piece&)>& visit) {
    for (std::int64_t br = row0 / m_blockRows; br * m_blockRows < row1; ++br) {
        for (std::int64_t bc = column0 / m_blockColumns; bc * m_blockColumns < column1; ++bc) {
            Result<const Block*> read = block(br, bc);
            if (!read) return read.error();
            const Block& b = *read.value();
            const std::int64_t r0 = std::max(row0, b.row0), r1 = std::min(row1, b.row0 + b.rows);
            const std::int64_t c0 = std::max(column0, b.column0);
            const std::int64_t c1 = std::min(column1, b.column0 + b.columns);
            if (r0 >= r1 || c0 >= c1) continue;
            const auto first =
                static_cast<std::size_t>((r0 - b.row0) * b.columns + (c0 - b.column0));
            visit(Piece{r0, c0, r1 - r0, c1 - c0, b.columns, b.heights.data() + first,
                        b.valid.data() + first});
        }
    }
    return {};
}

}  // namespace terrain::io::detail
