// RowFill: the fill of a window of one DEM row (VoidFill.h), the same whichever window of
// the raster a build reads (a band, a block, a shard of a region build). SourceVoids finds
// the source's voids the first time a row holds one, so a raster without voids is read once.
#pragma once

#include "VoidFill.h"
#include "terrain/base/Result.h"
#include "terrain/source/DemReader.h"

#include <cstdint>
#include <optional>
#include <span>

namespace terrain::io::detail {

/// A reader's voids, found on first use and then shared by every RowFill of it.
/// One thread at a time, like the reader.
class SourceVoids {
public:
    explicit SourceVoids(DemReader& reader) : m_reader(reader) {}
    Result<const VoidFill*> get() {
        if (!m_fill) {
            Result<VoidFill> found = VoidFill::find(m_reader);
            if (!found) return found.error();
            m_fill = std::move(found).value();
        }
        return &*m_fill;
    }

private:
    DemReader& m_reader;
    std::optional<VoidFill> m_fill;
};

class RowFill {
public:
    /// With `units` (a source of whole numbers, wholeSourceUnits), each fill is rounded to them.
    explicit RowFill(SourceVoids& voids, std::optional<VerticalTransform> units = std::nullopt)
        : m_voids(voids), m_units(units) {}

    /// Fills DEM row r's columns [a, a + row.size()), read into `row`, and marks `valid`
    /// (1 valid, 0 filled); the count filled.
    Result<std::int64_t> fill(std::int64_t r, std::int64_t a, std::span<float> row,
                              std::span<std::uint8_t> valid);

private:
    SourceVoids& m_voids;
    std::optional<VerticalTransform> m_units;
};

}  // namespace terrain::io::detail
