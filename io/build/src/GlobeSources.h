// GlobeSources: the geographic sources of one globe pyramid, composited by osgEarth's rule:
// at every point the finest source with a valid sample there wins. A source's voids are
// filled over the composite of the sources beneath it, the difference at the void's rim
// spread smoothly into the void (the delta-surface fill, VoidFill.h), so a void follows the
// coarser surface without a step at its rim (ETOPO's 37 km grid lies 2 km under SRTM's summit
// voids on Mount Rainier: the difference carries the SRTM's height, ETOPO the shape); with
// nothing beneath, by the membrane from the void's rim. The filled void shows, not the source
// beneath. Sources are held finest first (by their
// finest sample spacing); each knows its finest face level, the level down to which it makes
// patches exist.
// Where a finer source ends over a coarser one it is blended into it across a band at its
// edge (smoothstep, SeamBand.h) as wide as the height step there needs for the slope the
// blend adds to stay within the finer source's 99th-percentile slope, 24 pixels at least (a
// 90 m tile and a 37 km grid disagree by up to kilometres at the tile's edge: over a fixed
// 24 pixels that was a wall); the builder, the source check and the truth all use this
// composite.
#pragma once

#include "GeographicGrid.h"
#include "SourceSlopes.h"
#include "terrain/pyramid/PyramidManifest.h"

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace terrain::io {

class GlobeSources {
public:
    /// A resampled source's own samples (a projected DEM put onto `grid` by GDAL's warper,
    /// DemInfo::resampledFrom), each at its place: what Err(P) bounds for it, not the grid.
    struct OwnSamples {
        std::int64_t width = 0, height = 0;
        std::vector<float> heights;  ///< row-major; NaN: no data
        std::vector<double> latitudes, longitudes;
        std::int64_t validSamples = 0;
        double minHeight = 0.0, maxHeight = 0.0;  ///< over valid samples (0 if none)
    };

    struct Source {
        GeographicGrid grid;
        int finestFaceLevel = 0;
        std::string path;
        std::optional<OwnSamples> own;
        /// Where it is blended into the sources beneath at its edges, and how steep it is
        /// (what that blend may add): GlobeSources::read fits them.
        SeamBand band{};
        SourceSlopes slopes{};
        std::optional<double> noDataValue{};  ///< the raw value it declared (DemInfo)
    };

    /// `sources` in any order; kept finest first.
    explicit GlobeSources(std::vector<Source> sources);

    /// Reads every reader whole (each within memoryBudgetBytes / count), a resampled one's
    /// own samples too (placed by DemReader::placeOriginalSamples), and gives each its
    /// finest face level for patches of `quads` quads (finestFaceLevelOf, `oversampleLevels`
    /// below its spacing): what the builder does, and what the source check must do the
    /// same way. `shares`: the sources may hold 1/shares of the budget together (a builder's
    /// patches need the rest).
    static Result<GlobeSources> read(std::span<DemReader* const> readers,
                                     std::uint64_t memoryBudgetBytes, int quads,
                                     int oversampleLevels, unsigned shares = 1);

    const std::vector<Source>& sources() const { return m_sources; }
    int finestFaceLevel() const;  ///< over every source

    /// The composited value at a point: the finest valid sample; where none is valid, the
    /// finest source that holds the point (its filled value), then one whose edge pixels
    /// extend to it (GeographicGrid::at); 0 m beyond them all. `inside`: within some
    /// source's extent among those with finestFaceLevel ≥ `level` (what makes patches of that
    /// level exist).
    GeographicGrid::Resampled at(double latitudeDeg, double longitudeDeg, int level) const;

    /// The full-resolution surface at a point: the triangles between the pixel centres of the
    /// source the composite shows there, for both diagonals of the cell; nothing where no
    /// source covers the point (the bare ellipsoid).
    std::optional<std::pair<double, double>> surfaceHeightsAt(double latitudeDeg,
                                                              double longitudeDeg) const;

    /// The samples Err(P) bounds for source `k`: its own samples when it was resampled
    /// (OwnSamples), else its grid's; `measuredWidth` × `measuredHeight` of them.
    std::int64_t measuredWidth(std::size_t k) const;
    std::int64_t measuredHeight(std::size_t k) const;
    struct MeasuredSample {
        double latitudeDeg = 0.0, longitudeDeg = 0.0;
        double height = 0.0;  ///< the composite's there: the sample, or feathered at an edge
    };
    /// Measured sample (col, row) of source `k`, where the composite shows it: nothing for a
    /// no-data sample or one where another source shows.
    std::optional<MeasuredSample> measuredSample(std::size_t k, std::int64_t col,
                                                 std::int64_t row) const;

    /// The surface beneath source `k` at a point: the composite of the coarser sources, where
    /// one holds the point (a valid or a filled sample); what source k's voids are filled over.
    std::optional<double> beneath(std::size_t k, double latitudeDeg, double longitudeDeg) const;

    struct FilledSample {
        double latitudeDeg = 0.0, longitudeDeg = 0.0;
        double height = 0.0;            ///< the fill
        std::optional<double> beneath;  ///< the surface beneath it, if any
    };
    /// Grid sample (col, row) of source `k` when it is a filled one the composite shows.
    std::optional<FilledSample> filledSample(std::size_t k, std::int64_t col,
                                             std::int64_t row) const;

    /// The share of a source's slopes its seams stay within: the 99th percentile.
    static constexpr double kSeamSlopeShare = 0.99;
    /// Where source `k` is blended into a coarser one at its edges (docs/globe.md,
    /// "How it works"): nothing where it is blended into none. The seam's slope is the slope
    /// the blend adds to the composite: across the band the composite is c + w (f − c) of the
    /// source f and the one beneath c, whose gradient is the weighted mix of the two surfaces'
    /// own, w ∇f + (1 − w) ∇c, plus (f − c) ∇w: that last term, the step times the weight's
    /// slope, is what a too narrow band turns into a wall. Measured at every grid sample of
    /// the band where the composite blends, with ∇w by central differences (half a pixel
    /// either side) of the composite's own weight, in metres on the ellipsoid; the step
    /// (f − c) there too. The band is fitted to the source's slopes over a baseline as wide as
    /// the band (SourceSlopes::over, never above the gradient's percentile), so it stays
    /// within both but where the band is capped.
    std::optional<ManifestSeam> seamOf(std::size_t k) const;
    /// seamOf of every source that has one, finest first: the manifest's globe.seams.
    std::vector<ManifestSeam> seams() const;

private:
    static Result<OwnSamples> readOwnSamples(DemReader& reader, const GeographicGrid& grid,
                                             std::uint64_t memoryBudgetBytes, unsigned shares);
    struct Shown {
        int source = -1;  ///< the source whose value shows, or −1
        GeographicGrid::Resampled value;
        double feather = 1.0;  ///< the shown source's weight against the next coarser valid one
        bool blended = false;  ///< value is feathered into a coarser source's
        double under = 0.0;    ///< that coarser source's value, when blended
        int rank = 3;  ///< of value: 0 valid, 1 a filled void, 2 an extended edge pixel, 3 none
    };
    /// The composite of sources `first` … (the surface beneath source first − 1).
    Shown shownAt(double latitudeDeg, double longitudeDeg, int level, std::size_t first = 0) const;
    /// Fills every source's voids (GeographicGrid::fillVoids), over the sources beneath it.
    Status fillVoids();
    /// Fits every source's SeamBand to the steps at its edges (after fillVoids).
    void fitSeamBands();
    /// Source `k`'s weight against the coarser one it is blended into at a point (1 for the
    /// coarsest: nothing lies beneath it).
    double featherAt(std::size_t k, double latitudeDeg, double longitudeDeg) const;
    /// Grid sample (column, row) of source `k` minus the next coarser source valid there
    /// (what shownAt blends it into); nothing where none is.
    std::optional<double> blendStepAt(std::size_t k, std::int64_t column, std::int64_t row) const;

    std::vector<Source> m_sources;
};

/// The finest face level of a source on `grid` for patches of `quads` quads: as fine as its
/// samples at its centre (globeFinestLevelFor), and `oversampleLevels` finer
/// (PyramidBuildOptions::globeOversampleLevels), within kMaxGlobeFaceLevel. The whole build,
/// the region build and the source check decide it here, so they agree.
int finestFaceLevelOf(const GeographicGrid& grid, int quads, int oversampleLevels);
/// The same from a grid's edges and finest spacing alone (a source's header, before it is
/// read); a grid round the whole Earth (`wrapsLongitude`) is measured at longitude 0.
int finestFaceLevelOf(double southDeg, double northDeg, double westDeg, double eastDeg,
                      bool wrapsLongitude, double spacingMetres, int quads, int oversampleLevels);

}  // namespace terrain::io
