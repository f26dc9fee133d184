// SeamsInView: which of a globe pyramid's source seams (manifest globe.seams: where a finer
// source is blended into a coarser one across a band inside its edge) a frame shows, and the
// steepest slope their blends add, against their sources' 99th-percentile slope (issue 46,
// detector 6d, per frame; per run the manifest's figures are in bench.json "globe.seams").
#pragma once

#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/runtime/Camera.h"

#include <limits>
#include <span>
#include <vector>

namespace terrain::tools {

struct SeamsSeen {
    int seams = 0;  ///< seams with a drawn pixel in their band
    /// The largest seamSlope among them and that seam's sourceSlopeP99; NaN when none.
    double seamSlope = std::numeric_limits<double>::quiet_NaN();
    double sourceSlopeP99 = std::numeric_limits<double>::quiet_NaN();
};

/// The seams of `manifest` (a globe pyramid's; none on a plane) that the frame drawn with
/// `camera` shows: those with a drawn pixel of `depth` (reversed Z, rows bottom-up, 0 where
/// nothing is drawn) within its band's widest metres of its source's extent's edge, inside
/// the extent. Every `stridePx`-th pixel of every `stridePx`-th row is looked at.
SeamsSeen seamsInView(const io::PyramidManifest& manifest, const runtime::Camera& camera,
                      std::span<const float> depth, int stridePx = 2);

}  // namespace terrain::tools
