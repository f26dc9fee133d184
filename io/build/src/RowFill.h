// RowFill: the documented no-data fill (NoDataFill.h) of a window of one DEM row, exactly as
// the whole row's: where a run of no-data reaches past the window, the row's nearest valid
// samples beyond it are read from the source. What lets a region build (planar or globe) fill
// a window as the whole build fills the raster.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/source/DemReader.h"
#include "terrain/build/NoDataFill.h"

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace terrain::io::detail {

class RowFill {
public:
    explicit RowFill(DemReader& reader, std::optional<VerticalTransform> units = std::nullopt)
        : m_reader(reader), m_units(units) {}

    /// Fills DEM row r's columns [a, b), read into `row`, and marks `valid`; the count filled.
    Result<std::int64_t> fill(std::int64_t r, std::int64_t a, std::int64_t b, std::span<float> row,
                              std::span<std::uint8_t> valid);

private:
    // The first valid sample of row r from column `from` on, walking in `direction` (±1),
    // read in growing chunks: (column, height), or nothing when the row has none that way.
    Result<std::optional<std::pair<std::int64_t, float>>> nearestValid(std::int64_t r,
                                                                       std::int64_t from,
                                                                       int direction);

    DemReader& m_reader;
    std::optional<VerticalTransform> m_units;
    std::vector<float> m_scratch;
};

}  // namespace terrain::io::detail
