// MembraneFill: the smooth fill of a grid's free cells from its fixed ones, as a stretched
// membrane takes it: the discrete Laplace equation (each free cell the mean of its four
// neighbours) with the fixed cells as boundary values and nothing crossing the grid's own
// edges. What a no-data void is filled with where no source lies beneath it (VoidFill.h):
// smooth, and drawn from the void's whole boundary, not from one row.
#pragma once

#include <cstdint>
#include <span>

namespace terrain::io::detail {

/// Replaces the value of every free cell (fixed[i] == 0) of the `width` × `height` grid
/// `values` (row-major) by the membrane between the fixed cells; 0 where no cell is fixed.
/// Solved coarse to fine: each level of a pyramid of halved grids starts from the coarser
/// level's solution and relaxes (red-black SOR) until no cell moves by more than
/// kMembraneTolerance, or for a bounded number of sweeps. Deterministic; memory about
/// 7 bytes a cell.
void fillMembrane(std::int64_t width, std::int64_t height, std::span<float> values,
                  std::span<const std::uint8_t> fixed);

/// Metres: a level is relaxed until no cell moves by more than this in a sweep.
inline constexpr float kMembraneTolerance = 0.001f;

}  // namespace terrain::io::detail
