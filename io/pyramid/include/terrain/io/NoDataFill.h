// The documented fill of no-data samples (docs/pyramid-format.md, "No-data"): linear
// interpolation between the nearest valid samples west and east in the same row, so a
// renderer never draws a raw no-data value and the fill depends on nothing but the row.
#pragma once

#include <cstdint>
#include <span>

namespace terrain::io {

/// Replaces every NaN of `row` by the fill and writes 1 (valid) / 0 (filled) to `valid`
/// (same length). Returns the number of filled samples. A row without a valid sample
/// becomes 0 m.
std::int64_t fillNoDataRow(std::span<float> row, std::span<std::uint8_t> valid);

}  // namespace terrain::io
