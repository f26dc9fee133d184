// The documented fill of no-data samples (docs/pyramid-format.md, "No-data"): linear
// interpolation between the nearest valid samples west and east in the same row, so a
// renderer never draws a raw no-data value and the fill depends on nothing but the row.
#pragma once

#include "terrain/source/DemReader.h"

#include <cstdint>
#include <optional>
#include <span>

namespace terrain::io {

/// Replaces every NaN of `row` by the fill and writes 1 (valid) / 0 (filled) to `valid`
/// (same length). Returns the number of filled samples. A row without a valid sample
/// becomes 0 m. With `units` (a source that stores whole numbers, heights v · scale +
/// offset), each interpolated value is rounded to the nearest whole number of them, as the
/// source's own samples are: one fractional fill moves a tile of int16 metres from 1 m
/// steps to 1/16384 m ones or to the float's bits (HeightCodes.h), 14 bits a sample or more.
std::int64_t fillNoDataRow(std::span<float> row, std::span<std::uint8_t> valid,
                           const std::optional<VerticalTransform>& units = std::nullopt);

/// The nearest valid sample of the same row outside a window of it: `offset` counts from
/// the window's first sample (negative: west of the window; at least its size: east).
struct RowNeighbour {
    std::int64_t offset = 0;
    float value = 0.0f;
};

/// The same fill for a window of a longer row (a region build): `west` and `east` are the
/// row's nearest valid samples outside the window, or nothing where the row has none. The
/// window's samples come out exactly as fillNoDataRow fills them in the whole row.
std::int64_t fillNoDataWindow(std::span<float> window, std::span<std::uint8_t> valid,
                              const std::optional<VerticalTransform>& units,
                              std::optional<RowNeighbour> west, std::optional<RowNeighbour> east);

/// Whether a source of `info` stores whole numbers of its vertical units (an integer
/// sample type, not resampled): the `units` fillNoDataRow rounds its fill to.
std::optional<VerticalTransform> wholeSourceUnits(const DemInfo& info);

}  // namespace terrain::io
