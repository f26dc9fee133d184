// ProceduralTerrain: a seedable synthetic DEM of any size (up to 2^40 + 1 samples a side)
// that is evaluated on demand, window by window, and holds at known places the cases that
// break terrain LOD methods: a vertical cliff, single-sample spikes, a bit-flat lake and
// flat-topped mesas, on ridged multifractal mountains.
//
// Every sample is a pure function of (x, y, parameters): nothing of the raster is stored,
// so windows agree bit for bit where they overlap, whatever their size, position or the
// number of threads that fill them.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/source/Georeference.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace terrain::io {

/// Knobs of the procedural DEM. Feature positions and sizes are fractions of the DEM
/// (so a 1,025² and a 1,048,577² DEM of one seed show the same landscape, the larger in
/// more detail); the fractal adds octaves until their wavelength reaches two samples.
/// What must stay sharp at every size is measured in samples: the one-sample cliff step,
/// the one-sample spikes, the mesa sides.
struct ProceduralTerrainParameters {
    std::uint64_t seed = 1;
    std::int64_t widthSamples = 1025;   ///< Columns (x, east). 2^n + 1 fits the pyramid.
    std::int64_t heightSamples = 1025;  ///< Rows (y, south).
    /// Ground distance between samples. It places the DEM on the map
    /// (windowGeoreference) and does not change any height.
    double sampleSpacingM = 30.0;

    // Relief: gentle hills plus ridged multifractal mountains where a mask allows them.
    double hillHeightM = 400.0;       ///< Upper bound of the hills.
    double mountainHeightM = 3000.0;  ///< Upper bound of the mountains above the hills.
    double mountainFrequency = 2.0;   ///< Cycles of octave 0 across the DEM's shorter side.
    int octaves = 0;                  ///< Ridged octaves; 0 = down to a 2-sample wavelength.
    double roughness = 1.0;           ///< Musgrave's H: octave i has amplitude 2^(−i·H).
    double ridgeOffset = 1.0;         ///< Musgrave's ridged multifractal "offset".
    double ridgeGain = 2.0;           ///< Musgrave's ridged multifractal "gain".

    /// Height of the fault scarp: the west block stands exactly this much above the east
    /// block across the fault, between two horizontally adjacent samples. 0: no fault.
    double cliffHeightM = 1000.0;

    int plateauCount = 3;           ///< Mesas wanted (fewer if they do not fit).
    double plateauHeightM = 300.0;  ///< Mesa top above the terrain at its centre.
    double plateauRadius = 0.045;   ///< Fraction of the shorter side.
    int plateauSideSamples = 4;     ///< Width of the steep side, in samples.

    double lakeRadius = 0.08;  ///< Fraction of the shorter side; 0: no lake.

    int spikeCount = 8;           ///< Single-sample spikes wanted.
    double spikeHeightM = 250.0;  ///< Spike top above its highest neighbour.
};

/// A single-sample spike: exactly heightAboveNeighboursM above the highest of its 8
/// neighbours, none of which is a spike.
struct TerrainSpike {
    std::int64_t x = 0;
    std::int64_t y = 0;
    float heightM = 0.0F;                 ///< The spike sample's height.
    float heightAboveNeighboursM = 0.0F;  ///< heightM − max(8 neighbours), exactly.
};

/// Inclusive sample bounds.
struct SampleBox {
    std::int64_t minX = 0, minY = 0, maxX = -1, maxY = -1;
    bool contains(std::int64_t x, std::int64_t y) const {
        return x >= minX && x <= maxX && y >= minY && y <= maxY;
    }
};

/// A flat-topped mesa: every sample where plateauTopAt() names it has exactly topHeightM; the
/// outline is a noise-warped circle, the side falls over plateauSideSamples.
struct TerrainPlateau {
    double centreX = 0.0, centreY = 0.0;  ///< Samples.
    double radiusSamples = 0.0;           ///< Nominal radius of the top.
    float topHeightM = 0.0F;
    SampleBox topBounds;  ///< Holds every top sample (clipped to the DEM).
};

/// The lake: every sample with isLake() has exactly levelM (bit-identical floats); the
/// shore is a noise-warped circle around which the land rises smoothly.
struct TerrainLake {
    double centreX = 0.0, centreY = 0.0;  ///< Samples.
    double radiusSamples = 0.0;           ///< Nominal radius.
    float levelM = 0.0F;
    SampleBox bounds;  ///< Holds every lake sample.
};

class ProceduralTerrain {
public:
    /// Every height is a multiple of this (1/1024 m), so that heights below
    /// kExactHeightLimitM are exact floats and feature steps (cliff, spikes) are exact
    /// differences of floats.
    static constexpr double kHeightQuantumM = 1.0 / 1024.0;
    static constexpr double kExactHeightLimitM = 8192.0;
    static constexpr std::int64_t kMinSideSamples = 65;
    static constexpr std::int64_t kMaxSideSamples = (std::int64_t{1} << 40) + 1;
    static constexpr int kMaxOctaves = 48;

    /// Checks the parameters and places the features. Errors name the bad parameter.
    static Result<ProceduralTerrain> create(const ProceduralTerrainParameters& parameters);

    const ProceduralTerrainParameters& parameters() const { return m_parameters; }
    std::int64_t width() const { return m_parameters.widthSamples; }
    std::int64_t height() const { return m_parameters.heightSamples; }
    int octaves() const { return static_cast<int>(m_ridgedOctaves.size()); }

    /// Height in metres of sample (x, y), 0 ≤ x < width(), 0 ≤ y < height(). y grows
    /// south (down the image rows). Any thread.
    float sample(std::int64_t x, std::int64_t y) const;

    /// Fills the window of `width` × `height` samples whose north-west sample is (x0, y0):
    /// out[(y − y0)·width + (x − x0)], row 0 = y0 (north), rows run south like image rows.
    /// The window must lie in the DEM and out must hold width·height floats. Rows are
    /// split over `threadCount` std::threads (0: one per hardware thread); the result does
    /// not depend on it. Any thread.
    void fillWindow(std::int64_t x0, std::int64_t y0, std::int64_t width, std::int64_t height,
                    std::span<float> out, unsigned threadCount = 1) const;

    /// Placement of the window whose north-west sample is (x0, y0): sample (x, y) is the
    /// centre of a pixel whose area is [x·s, (x+1)·s] east and [(H−1−y)·s, (H−y)·s]
    /// north, s = sample spacing, H = height(); the whole DEM spans [0, W·s] × [0, H·s].
    Georeference windowGeoreference(std::int64_t x0, std::int64_t y0,
                                    int epsg = Georeference::kUnknownProjectedCrs) const;

    // --- The features, for tests and tools ----------------------------------------------

    /// False when cliffHeightM is 0.
    bool hasCliff() const { return m_cliffHeightM > 0.0; }
    /// The fault crosses every row: in row y, columns ≤ cliffColumn(y) are the west (high)
    /// block and sample (cliffColumn(y), y) stands exactly cliffHeightM() above
    /// (cliffColumn(y) + 1, y). 0 ≤ cliffColumn(y) ≤ width() − 2.
    std::int64_t cliffColumn(std::int64_t y) const;
    float cliffHeightM() const { return static_cast<float>(m_cliffHeightM); }

    std::span<const TerrainSpike> spikes() const { return m_spikes; }

    const std::optional<TerrainLake>& lake() const { return m_lake; }
    bool isLake(std::int64_t x, std::int64_t y) const;

    std::span<const TerrainPlateau> plateaus() const { return m_plateaus; }
    /// Index into plateaus() of the mesa whose flat top holds (x, y), if any.
    std::optional<std::size_t> plateauTopAt(std::int64_t x, std::int64_t y) const;

    /// A conservative bound on every height (they all lie in [0, maxHeightBoundM()]).
    double maxHeightBoundM() const { return m_heightBoundM; }

private:
    // One octave of gradient noise: the lattice position of sample (x, y) is
    // (x·scale + offsetX, y·scale + offsetY) (see src/GradientNoise.h).
    struct Octave {
        double scale = 1.0;
        double offsetX = 0.0, offsetY = 0.0;
        std::uint64_t salt = 0;
        double amplitude = 1.0;
    };
    // A warped-circle region (lake or mesa): normalised distance
    // d = |p − centre| / radius + warp·noise(p); the region is d ≤ 1, and heights blend
    // from `level` back to the terrain over rimSamples beyond it.
    struct WarpedDisc {
        double centreX = 0.0, centreY = 0.0, radius = 1.0;
        double warp = 0.0;
        double rimSamples = 0.0;
        double level = 0.0;  // exact height inside (quantised)
        Octave warpNoise;
        SampleBox influence;  // every sample the disc changes
    };
    struct RowScratch;

    ProceduralTerrain() = default;

    Status placeFeatures();
    void baseRow(std::int64_t y, std::int64_t xStart, std::size_t count, RowScratch& scratch) const;
    void discDistances(const WarpedDisc& disc, std::int64_t y, std::int64_t xStart,
                       std::size_t count, RowScratch& scratch) const;
    void evaluateRow(std::int64_t y, std::int64_t x0, std::int64_t count, float* out,
                     RowScratch& scratch) const;
    float evaluateSample(std::int64_t x, std::int64_t y) const;
    double heightBeforeFeatures(std::int64_t x, std::int64_t y) const;
    bool insideDisc(const WarpedDisc& disc, std::int64_t x, std::int64_t y) const;
    bool touchesCliff(const SampleBox& box, std::int64_t margin) const;

    ProceduralTerrainParameters m_parameters;
    double m_unitSamples = 1.0;  // samples per DEM-relative unit (the shorter side − 1)
    std::vector<Octave> m_ridgedOctaves;
    std::array<Octave, 3> m_hillOctaves{};
    std::array<Octave, 2> m_maskOctaves{};
    double m_ridgedScale = 1.0;  // 1 / (bound of the ridged sum)
    double m_heightBoundM = 0.0;

    double m_cliffHeightM = 0.0;
    double m_cliffColumnAtTop = 0.0;  // fault column at y = 0 (fractional)
    double m_cliffColumnsPerRow = 0.0;

    std::vector<TerrainSpike> m_spikes;
    std::optional<TerrainLake> m_lake;
    std::vector<TerrainPlateau> m_plateaus;
    std::vector<WarpedDisc> m_discs;  // m_plateaus first, then the lake (applied last)
};

}  // namespace terrain::io
