// GeographicBlocks: a geographic source read block by block, for the globe's region build
// (GlobeShardTiling.cpp): what GeographicGrid holds whole, within a fixed cache, whatever the
// raster's size. Every sample is filled exactly as GeographicGrid::read fills it (each void
// solved alone from its own box, VoidFill.h, RowFill.h), and `at` is
// GeographicGrid::at to the bit, so a region build resamples as the whole build does.
// One thread at a time, like the reader under it.
#pragma once

#include "GeographicGrid.h"
#include "RowFill.h"
#include "terrain/base/Result.h"
#include "terrain/source/DemReader.h"

#include <cstdint>
#include <functional>
#include <list>
#include <memory>
#include <unordered_map>
#include <vector>

namespace terrain::io::detail {

/// Sets `grid`'s poles (GeographicGrid::poleRow) from its source's edge rows, read and filled
/// as GeographicGrid::read fills them, so that a region build's fan meets the pole where the
/// whole build's does. Nothing is read for a grid without a pole.
Status readPoles(DemReader& reader, SourceVoids& voids, GeographicGrid& grid);

class GeographicBlocks {
public:
    /// `grid` is the source's description (GeographicGrid::describe); blocks of `blockRows`
    /// × `blockColumns` samples (large ones for reading a region whole, small ones for points
    /// here and there), at least four cached whatever `cacheBytes` says.
    GeographicBlocks(DemReader& reader, SourceVoids& voids, const GeographicGrid& grid,
                     std::uint64_t cacheBytes, std::int64_t blockRows, std::int64_t blockColumns);

    /// GeographicGrid::at of the whole source.
    Result<GeographicGrid::Resampled> at(double latitudeDeg, double longitudeDeg);

    /// Samples of rows [row0, row1) and columns [column0, column1), block by block: `visit`
    /// gets each piece's first row and column, its size, and its filled heights and validity
    /// (row-major, `stride` apart).
    struct Piece {
        std::int64_t row0 = 0, column0 = 0, rows = 0, columns = 0, stride = 0;
        const float* heights = nullptr;
        const std::uint8_t* valid = nullptr;
    };
    Status forEachPiece(std::int64_t row0, std::int64_t row1, std::int64_t column0,
                        std::int64_t column1, const std::function<void(const Piece&)>& visit);

    /// Blocks read from the source so far (a block read again after it left the cache counts
    /// again).
    std::int64_t blocksRead() const { return m_blocksRead; }

private:
    struct Block {
        std::int64_t row0 = 0, column0 = 0, rows = 0, columns = 0;
        std::vector<float> heights;
        std::vector<std::uint8_t> valid;
    };
    Result<const Block*> block(std::int64_t blockRow, std::int64_t blockColumn);

    DemReader& m_reader;
    const GeographicGrid& m_grid;
    std::int64_t m_blockRows, m_blockColumns;
    RowFill m_fill;
    std::size_t m_capacity;
    std::list<std::uint64_t> m_recent;  // most recent first
    struct Cached {
        std::unique_ptr<Block> block;
        std::list<std::uint64_t>::iterator recent;
    };
    std::unordered_map<std::uint64_t, Cached> m_cache;
    std::int64_t m_blocksRead = 0;
};

}  // namespace terrain::io::detail
