// SourceSlopes: how steep a globe source is at the scales a seam between it and a coarser
// source is seen at (GlobeSources, SeamBand.h): percentiles of its slope at its pixels and
// over longer baselines along its rows and columns. A 90 m mountain tile's steepest 1 % lie
// above 40° from pixel to pixel but far less over a kilometre or two; a blend ramp kilometres
// wide is judged against the latter, or it stands out as a wall the terrain itself never
// draws that long.
#pragma once

#include "GeographicGrid.h"

#include <vector>

namespace terrain::io {

class SourceSlopes {
public:
    /// The `share` (0 … 1) percentiles of `grid`'s valid samples, over baselines up to
    /// `longestPixels`. To a hundredth of a degree; at most about a million pairs a baseline
    /// (evenly spread), so a large source costs no more than a small one.
    SourceSlopes(const GeographicGrid& grid, double share, double longestPixels);
    SourceSlopes() = default;

    /// At each valid sample with four valid neighbours, the gradient's size by central
    /// differences over the pixel's ground size, metres per metre (0 without such a sample).
    double gradient() const { return m_gradient; }
    /// |h(x + L) − h(x)| / L between valid samples `pixels` apart along a row (`eastWest`) or a
    /// column, L in metres; between the baselines measured, interpolated in log L; at most
    /// gradient().
    double over(bool eastWest, double pixels) const;

private:
    std::vector<double> m_baselines;               // pixels, increasing
    std::vector<double> m_eastWest, m_northSouth;  // per baseline
    double m_gradient = 0.0;
};

}  // namespace terrain::io
