// PlanetImagery: the virtual planet's colours (issue 47, item 5), an imagery layer generated
// where a reader would read it, as the planet's heights are (VirtualPlanetPyramid.h), so the
// first picture of the planet reads as one: sea by depth, sea ice, beaches, forest, grass and
// desert in latitude bands, rock on steep slopes, snow above a snow line that falls towards
// the poles, ice caps.
//
// Every texel, border included, is coloured at its own face point's direction (ImageryTile.h:
// the border continues the grid across patch and cube-face edges), from the planet low-passed
// to the texel's footprint (ProceduralPlanet::lowPassed, σ = 0.8 texel): a coarse tile shows
// the waves it can resolve, not aliases of finer ones, so it does not shimmer as the view
// moves. What the filter took away is added back as statistics (lostRoughness: the planet's
// waves span it all, so they are the same everywhere): the slope is the finite difference of
// the low-passed heights one texel either side with the lost slope's variance added, and the
// coast, beaches and snow line soften by the lost height's spread, so a coarse tile looks
// like its children averaged (as much rock, sand and snow), not like a smoother planet. Colours are
// chosen and mixed in linear light and stored sRGB-encoded. Every tile is opaque: the sea is
// coloured by depth here, as the draw's water is (terrain_shading.glsl's waterTint), because an
// imagery layer that covers the planet must cover the sea too (an alpha-0 sea would show the tint
// beneath, or whatever layer lies under it, not water).
#pragma once

#include "terrain/pyramid/ImageryTileSource.h"
#include "terrain/source/ProceduralPlanet.h"

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace terrain::io {

/// What a texel's colour depends on.
struct PlanetGround {
    double heightAboveSeaM = 0.0;  ///< negative: depth under the sea
    double slope = 0.0;            ///< |∇h|, metres per metre at the texel's scale
    double latitudeDeg = 0.0;      ///< geodetic
    double moisture = 0.0;         ///< −1 (dry) … 1 (wet): the climate's slow variation
    /// The texel's size, metres: the coast is blended over the height's change across it,
    /// so it neither aliases nor steps a whole texel.
    double texelSizeM = 1.0;
    /// How much the height varies within the texel (the standard deviation of the waves too
    /// fine for it), metres: a coarse texel's coast, beach and snow line are as soft as the
    /// share of its finer texels that are sea, sand or snow.
    double heightSpreadM = 0.0;
};

/// The colour of `ground`, linear light (each channel 0 … 1). Pure: the tests check its
/// classes (sea, snow, rock, …) directly.
std::array<float, 3> planetGroundColour(const PlanetGround& ground);

/// linear light (0 … 1) to an sRGB-encoded byte (IEC 61966-2-1).
std::uint8_t encodeSrgb(float linear);

class PlanetImagery final : public ImageryTileSource {
public:
    /// The layer `layerName` of the planet `planet`, whose sea lies at `seaLevelM` above the
    /// ellipsoid, with tiles at layout levels ManifestGlobe::kLevelOffset … `finestLevel`.
    PlanetImagery(const ProceduralPlanet& planet, double seaLevelM, int finestLevel,
                  std::string layerName);

    /// Generates tile `id` (the calling thread's source: it keeps scratch rows between tiles).
    /// Errors name the layer and the tile: outside the layer's levels or the faces.
    Status readTile(const PatchId& id, ImageryTile& out) override;

    /// The climate's moisture at a unit direction (−1 … 1): a few slow waves from the
    /// planet's seed, so the bands wander by latitude and deserts, grass and forest alternate.
    double moistureAt(double x, double y, double z) const;

    /// The ground at face point `point` seen by the texels of face level `faceLevel`: what
    /// readTile computes for a texel centred there (its slope from the heights one texel
    /// either side along s and t). The calling thread's source, as readTile: it makes the
    /// level's low-passed planet the first time a level is asked.
    PlanetGround groundAt(int faceLevel, const globe::FacePoint& point) const;

private:
    struct MoistureWave {
        double x = 0.0, y = 0.0, z = 0.0, phase = 0.0, amplitude = 0.0;
    };
    static constexpr int kMoistureWaves = 6;

    // The planet as a face level's texels see it: low-passed, and what the filter took away.
    struct LevelPlanet {
        ProceduralPlanet planet;
        double lostSlopeVariance = 0.0;
        double heightSpreadM = 0.0;
    };
    const LevelPlanet& levelPlanet(int faceLevel) const;

    ProceduralPlanet m_planet;
    double m_seaLevelM = 0.0;
    int m_finestLevel = 0;
    std::string m_layerName;
    std::array<MoistureWave, kMoistureWaves> m_moisture{};
    double m_moistureNorm = 1.0;
    /// The planet low-passed to each face level's texels, made when a level is first asked.
    mutable std::vector<std::optional<LevelPlanet>> m_levels;
    // Scratch, reused between tiles: the cube coordinate of each column and row (one extra
    // either side for the differences), the directions and heights of the grid.
    std::vector<double> m_columnCube, m_rowCube;
    std::vector<double> m_height;
    std::vector<double> m_direction;  ///< x, y, z per grid point
};

}  // namespace terrain::io
