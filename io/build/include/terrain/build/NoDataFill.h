// The documented fill of no-data samples (docs/pyramid-format.md, "No-data"), so a renderer
// never draws a raw no-data value: each void (a 4-connected run of no-data samples) takes the
// surface of the source beneath it plus the difference at its rim spread smoothly into it
// (the delta-surface fill), or where nothing lies beneath, the membrane from its whole rim.
// What a build does to each source (VoidFill.h), for a raster held whole.
#pragma once

#include "terrain/source/DemReader.h"

#include <cstdint>
#include <functional>
#include <optional>
#include <span>

namespace terrain::io {

/// The surface beneath a raster at its sample (column, row), or nothing where none is.
using SurfaceBeneath = std::function<std::optional<double>(std::int64_t column, std::int64_t row)>;

/// Replaces every NaN of the `width` × `height` raster `heights` (row-major) by the fill and
/// writes 1 (valid) / 0 (filled) to `valid` (same size); the number of samples filled. A void
/// is filled over `beneath` where it gives a height at every sample of the void and its rim.
/// A raster without a valid sample becomes 0 m. With `units` (a source that stores whole
/// numbers, heights v · scale + offset), each filled value is rounded to the nearest whole
/// number of them, as the source's own samples are: one fractional fill moves a tile of int16
/// metres from 1 m steps to 1/16384 m ones or to the float's bits (HeightCodes.h), 14 bits a
/// sample or more.
std::int64_t fillNoData(std::int64_t width, std::int64_t height, std::span<float> heights,
                        std::span<std::uint8_t> valid,
                        const std::optional<VerticalTransform>& units = std::nullopt,
                        const SurfaceBeneath* beneath = nullptr);

/// Whether a source of `info` stores whole numbers of its vertical units (an integer
/// sample type, not resampled): the `units` fillNoData rounds its fill to.
std::optional<VerticalTransform> wholeSourceUnits(const DemInfo& info);

}  // namespace terrain::io
