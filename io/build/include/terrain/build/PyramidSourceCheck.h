// Re-checks a pyramid's error bounds against its source DEM: every valid DEM sample must
// lie within Err(P) of the surface of the patch that covers it, at every level, whichever
// diagonal the GPU's tessellator draws (terrain-inspect --verify --source).
#pragma once

#include "terrain/base/Result.h"
#include "terrain/source/DemReader.h"
#include "terrain/pyramid/PyramidReader.h"

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace terrain::io {

struct ErrorBoundViolation {
    PatchId patch;
    std::int64_t x = 0;  ///< DEM sample
    std::int64_t y = 0;
    double distanceM = 0.0;
    float boundM = 0.0f;
    /// The stored sample at (x, y) differs from the source's by distanceM, more than the
    /// patch's δ (boundM = quantError), rather than the surface passing beyond Err(P).
    bool stored = false;
};

struct SourceCheckReport {
    std::int64_t samplesChecked = 0;  ///< valid DEM samples × levels
    std::int64_t violationCount = 0;
    std::vector<ErrorBoundViolation> violations;  ///< the first kMaxListed
    /// Per level, the largest distance / Err(P) over patches with Err(P) > 0: how tight
    /// the bound is (≤ 1 when it holds).
    std::vector<double> tightestRatio;
    /// The stored samples themselves (planar pyramids of an unresampled source): each
    /// level's sample at a source sample must be within the patch's δ (quantError, 0 when
    /// lossless) of it. (sample, level) pairs checked, and the largest difference per level.
    std::int64_t storedSamplesChecked = 0;
    std::int64_t storedViolationCount = 0;
    std::vector<double> largestStoredDifference;
    /// Globe pyramids: the filled samples of a source with a surface beneath it (its voids,
    /// filled over the sources beneath, docs/pyramid-format.md, "No-data"), drawn by the finest
    /// patch there, against that surface: how many, the largest distance, the largest
    /// difference between the source and the surface beneath at a void's rim, and how many lie
    /// further from the surface than that difference, the patch's Err(P) and
    /// kFilledToleranceM (the fill spreads the rim's difference, so none should).
    std::int64_t filledSamplesChecked = 0;
    double largestFilledDeviationM = 0.0;
    double largestRimDifferenceM = 0.0;
    std::int64_t filledBeyondRimCount = 0;
    static constexpr double kFilledToleranceM = 0.5;
    static constexpr std::size_t kMaxListed = 20;
};

/// Streams the source once, row by row, keeping one row of patches per level, and checks
/// both the surfaces (Err(P)) and the stored samples on each level's grid (δ). The source
/// must have the pyramid's raster size. A resampled source (a rotated grid,
/// DemInfo::resampledFrom) is checked by its own samples instead, each where it lies
/// between the pyramid's (`x`, `y` of a violation are its stored column and row), reading
/// the rows that cross each patch row. Calling thread (plus one worker per level).
/// For a globe pyramid (version 3) the source is any DEM it was built from, opened as the
/// build opened it (DemOpenOptions::geographicGrid): each valid sample is checked at every
/// face level along its ellipsoid normal against the drawn triangles of the patch holding it
/// (GlobePatchSurface); a projected source by its own samples, each placed through its CRS;
/// `x`, `y` of a violation are the source sample, and levels above the faces report a ratio
/// of 0.
Result<SourceCheckReport> checkErrorBoundsAgainstSource(
    const std::filesystem::path& pyramidDir, DemReader& source,
    const std::function<void(double fraction)>& progress = {});

/// The same for a pyramid built from several sources: a globe pyramid's composited sources
/// (each checked where it wins, GlobePyramidBuilder.h), or a planar pyramid's one source.
Result<SourceCheckReport> checkErrorBoundsAgainstSources(
    const std::filesystem::path& pyramidDir, std::span<DemReader* const> sources,
    const std::function<void(double fraction)>& progress = {});

}  // namespace terrain::io
