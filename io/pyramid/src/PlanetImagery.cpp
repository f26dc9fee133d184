#include "terrain/pyramid/PlanetImagery.h"

#include "terrain/globe/CubeSphere.h"
#include "terrain/globe/Wgs84.h"
#include "terrain/pyramid/GlobeLayout.h"
#include "terrain/source/SplitMix64.h"

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace terrain::io {

namespace {

constexpr std::uint64_t kMoistureSalt = 0x4D4F495354ULL;  // "MOIST"

// Distances on the unit sphere become metres at the ellipsoid's mean radius: the slope needs
// them to a few per cent only.
constexpr double kRadiusM =
    (2.0 * globe::Wgs84::kEquatorialRadius + globe::Wgs84::kPolarRadius) / 3.0;

// A texel of face level l spans about a face's quarter turn over its 2^l · 248 interior
// texels (the tangent adjustment keeps the spacing within √2 of that over the face).
double texelAngle(int faceLevel) {
    return std::numbers::pi / 2.0 / (std::ldexp(1.0, faceLevel) * kImageryInteriorTexels);
}
// The footprint's Gaussian σ, in texels: 0.8 leaves 4 % of a wave at the texels' Nyquist
// frequency, 45 % of one four texels long and 82 % of one eight long (a box of one texel
// would leave 64 %, 90 % and 97 %, and alias: the plane waves' crossings show as a
// texel-sized hatching where a smoothstep cuts them).
constexpr double kFootprintSigmaTexels = 0.8;

float srgbToLinear(double encoded) {
    const double c = encoded / 255.0;
    return static_cast<float>(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
}

using Colour = std::array<float, 3>;

Colour srgb(int r, int g, int b) { return {srgbToLinear(r), srgbToLinear(g), srgbToLinear(b)}; }

Colour mix(const Colour& a, const Colour& b, double t) {
    const auto f = static_cast<float>(std::clamp(t, 0.0, 1.0));
    return {a[0] + (b[0] - a[0]) * f, a[1] + (b[1] - a[1]) * f, a[2] + (b[2] - a[2]) * f};
}

double smoothstep(double edge0, double edge1, double x) {
    const double t = std::clamp((x - edge0) / (edge1 - edge0), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

// The land's vegetation by "climate latitude" (the latitude plus the height's cooling and the
// moisture's wander): a dry and a wet colour at each key, interpolated between keys.
struct Biome {
    double latitudeDeg;
    Colour dry, wet;
};

struct Palette {
    Colour deepSea = srgb(14, 38, 88), openSea = srgb(28, 78, 138), shelf = srgb(70, 150, 170);
    Colour seaIce = srgb(222, 232, 240);
    Colour sand = srgb(218, 204, 160);
    Colour rock = srgb(118, 108, 98), coldRock = srgb(128, 128, 130);
    Colour snow = srgb(242, 245, 250);
    std::array<Biome, 8> biomes{{
        {0.0, srgb(150, 142, 78), srgb(30, 78, 30)},      // savanna / rain forest
        {14.0, srgb(172, 152, 92), srgb(46, 96, 36)},     // savanna / forest
        {24.0, srgb(212, 184, 132), srgb(138, 140, 76)},  // desert / grassland
        {34.0, srgb(178, 162, 112), srgb(96, 130, 60)},   // steppe / grass
        {46.0, srgb(122, 136, 76), srgb(50, 96, 42)},     // grass / temperate forest
        {58.0, srgb(78, 98, 60), srgb(36, 72, 44)},       // boreal forest
        {66.0, srgb(128, 122, 98), srgb(108, 116, 86)},   // tundra
        {90.0, srgb(150, 146, 132), srgb(140, 142, 128)},
    }};
};

const Palette& palette() {
    static const Palette kPalette;  // immutable, made once
    return kPalette;
}

Colour biomeColour(const Palette& p, double climateLatitudeDeg, double wetness) {
    const auto& b = p.biomes;
    const double l = std::clamp(climateLatitudeDeg, 0.0, 90.0);
    std::size_t i = 1;
    while (i + 1 < b.size() && b[i].latitudeDeg < l) ++i;
    const double t = (l - b[i - 1].latitudeDeg) / (b[i].latitudeDeg - b[i - 1].latitudeDeg);
    return mix(mix(b[i - 1].dry, b[i].dry, t), mix(b[i - 1].wet, b[i].wet, t), wetness);
}

// Where the ground is white: the climate latitude past which snow lies all year. With the
// height's 12° per kilometre (the lapse rate, 6.5 K/km, over the 0.5–0.7 K per degree the
// air cools towards the poles), the snow line is about 5.8 km high at the equator, 2.3 km at
// 45° and sea level at 70°: the ice caps.
constexpr double kSnowClimateLatitudeDeg = 70.0;
constexpr double kDegreesPerKm = 12.0;

// The texel's ground from the heights at its centre and one texel either side along s and t.
struct Cross {
    glm::dvec3 centre, sMinus, sPlus, tMinus, tPlus;  // unit directions
    double h, hsMinus, hsPlus, htMinus, htPlus;       // above the sea, metres
};

PlanetGround groundOf(const Cross& c, double moisture, double lostSlopeVariance,
                      double heightSpreadM) {
    // The gradient G in the tangent plane from two chords that need not be orthogonal (the
    // cube grid's lines cross at up to 30° off a right angle near a face's corners):
    // G · es = dhs, G · et = dht, G in their plane.
    const glm::dvec3 es = (c.sPlus - c.sMinus) * kRadiusM;
    const glm::dvec3 et = (c.tPlus - c.tMinus) * kRadiusM;
    const double dhs = c.hsPlus - c.hsMinus;
    const double dht = c.htPlus - c.htMinus;
    const double ss = glm::dot(es, es), tt = glm::dot(et, et), st = glm::dot(es, et);
    const double determinant = ss * tt - st * st;
    const double slope2 =
        determinant > 0.0 ? (dhs * dhs * tt - 2.0 * dhs * dht * st + dht * dht * ss) / determinant
                          : 0.0;
    PlanetGround g;
    g.heightAboveSeaM = c.h;
    g.slope = std::sqrt(std::max(slope2, 0.0) + lostSlopeVariance);
    g.latitudeDeg = std::asin(std::clamp(c.centre.z, -1.0, 1.0)) * (180.0 / std::numbers::pi);
    g.moisture = moisture;
    g.texelSizeM = 0.25 * (std::sqrt(ss) + std::sqrt(tt));
    g.heightSpreadM = heightSpreadM;
    return g;
}

}  // namespace

std::array<float, 3> planetGroundColour(const PlanetGround& ground) {
    const Palette& p = palette();
    const double h = ground.heightAboveSeaM;
    const double absLatitude = std::abs(ground.latitudeDeg);

    // The sea: lighter over the shelves, darker with depth (as the draw's waterTint), frozen
    // towards the poles.
    const double depth = std::max(-h, 0.0);
    Colour sea = mix(p.shelf, p.openSea, smoothstep(0.0, 200.0, depth));
    sea = mix(sea, p.deepSea, std::sqrt(std::clamp((depth - 200.0) / 4000.0, 0.0, 1.0)));
    // Pack ice: nearer the equator along the coasts and where the climate is wet, so its
    // edge follows the sea floor rather than a circle of latitude.
    const double iceEdgeDeg = 70.0 - 8.0 * ground.moisture + std::min(depth, 4000.0) / 300.0;
    sea = mix(sea, p.seaIce, smoothstep(iceEdgeDeg - 1.5, iceEdgeDeg + 1.5, absLatitude));

    // The land: vegetation by climate latitude and moisture; beaches just above the sea
    // where the ground is gentle; rock where it is steep; snow above the snow line, sliding
    // off the steepest rock. A coarse texel's finer heights spread over ±1.25 σ or so: the
    // bands of sand and snow soften by it, as its finer texels' colours average.
    const double spread = 1.25 * ground.heightSpreadM;
    const double climateLatitude =
        absLatitude + kDegreesPerKm * std::max(h, 0.0) / 1000.0 + 3.0 * ground.moisture;
    Colour land =
        biomeColour(p, climateLatitude, std::clamp(0.6 + 0.6 * ground.moisture, 0.0, 1.0));
    const double beach = (1.0 - smoothstep(4.0, 30.0 + spread, h)) / (1.0 + spread / 30.0) *
                         (1.0 - smoothstep(0.05, 0.2, ground.slope)) *
                         (1.0 - smoothstep(55.0, 65.0, absLatitude));
    land = mix(land, p.sand, beach);
    const Colour rock = mix(p.rock, p.coldRock, smoothstep(50.0, 70.0, climateLatitude));
    land = mix(land, rock, smoothstep(0.22, 0.42, ground.slope));
    const double snowBand = 2.0 + kDegreesPerKm * spread / 1000.0;
    const double snow = smoothstep(kSnowClimateLatitudeDeg - snowBand,
                                   kSnowClimateLatitudeDeg + snowBand, climateLatitude) *
                        (1.0 - 0.6 * smoothstep(0.4, 0.6, ground.slope));
    land = mix(land, p.snow, snow);

    // The coast blended over the height's change across the texel and within it (as the
    // draw's coast is over a pixel's), so it neither aliases nor jumps a texel.
    const double across = ground.slope * ground.texelSizeM;
    const double coastWidthM = std::max(std::sqrt(across * across + spread * spread), 1.0);
    return mix(sea, land, 0.5 + h / coastWidthM);
}

std::uint8_t encodeSrgb(float linear) {
    // A table over 4096 steps of linear light: below the 8-bit code's own resolution
    // everywhere but the darkest codes, where the table holds the exact value.
    struct Table {
        std::array<std::uint8_t, 4097> codes{};
        Table() {
            for (std::size_t i = 0; i < codes.size(); ++i) {
                const double c = static_cast<double>(i) / 4096.0;
                const double e =
                    c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
                codes[i] = static_cast<std::uint8_t>(std::lround(std::clamp(e, 0.0, 1.0) * 255.0));
            }
        }
    };
    static const Table kTable;  // immutable, made once
    const float clamped = std::clamp(linear, 0.0f, 1.0f);
    return kTable.codes[static_cast<std::size_t>(std::lround(clamped * 4096.0f))];
}

PlanetImagery::PlanetImagery(const ProceduralPlanet& planet, double seaLevelM, int finestLevel,
                             std::string layerName)
    : m_planet(planet),
      m_seaLevelM(seaLevelM),
      m_finestLevel(finestLevel),
      m_layerName(std::move(layerName)),
      m_levels(static_cast<std::size_t>(kMaxGlobeFaceLevel) + 1) {
    // Slow waves through 3-D space, as the planet's own (so no pole and no seam): wavelengths
    // from about 16,000 km down to 1,300 km, the finer ones weaker.
    detail::SplitMix64 rng(detail::mix64(planet.parameters().seed ^ kMoistureSalt));
    double frequency = 2.5;
    double amplitude = 1.0;
    m_moistureNorm = 0.0;
    for (MoistureWave& wave : m_moisture) {
        const double z = rng.uniform(-1.0, 1.0);
        const double azimuth = rng.uniform(0.0, 2.0 * std::numbers::pi);
        const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
        const double f = frequency * rng.uniform(0.85, 1.15);
        wave = {f * r * std::cos(azimuth), f * r * std::sin(azimuth), f * z,
                rng.uniform(0.0, 2.0 * std::numbers::pi), amplitude};
        m_moistureNorm += amplitude;
        frequency *= 1.65;
        amplitude *= 0.75;
    }
    // The sum's spread is well inside its bound: scale it so that it reaches ±1 often.
    m_moistureNorm *= 0.55;
}

double PlanetImagery::moistureAt(double x, double y, double z) const {
    double sum = 0.0;
    for (const MoistureWave& w : m_moisture)
        sum += w.amplitude * std::sin(w.x * x + w.y * y + w.z * z + w.phase);
    return std::clamp(sum / m_moistureNorm, -1.0, 1.0);
}

const PlanetImagery::LevelPlanet& PlanetImagery::levelPlanet(int faceLevel) const {
    std::optional<LevelPlanet>& level = m_levels[static_cast<std::size_t>(faceLevel)];
    if (!level) {
        const double sigma = kFootprintSigmaTexels * texelAngle(faceLevel);
        const ProceduralPlanet::Roughness lost = m_planet.lostRoughness(sigma, kRadiusM);
        level = LevelPlanet{m_planet.lowPassed(sigma), lost.slopeVariance,
                            std::sqrt(lost.heightVarianceM2)};
    }
    return *level;
}

PlanetGround PlanetImagery::groundAt(int faceLevel, const globe::FacePoint& point) const {
    const LevelPlanet& level = levelPlanet(faceLevel);
    const ProceduralPlanet& planet = level.planet;
    const double step = 1.0 / (std::ldexp(1.0, faceLevel) * kImageryInteriorTexels);
    const auto at = [&](double s, double t) { return globe::directionOf(point.face, s, t); };
    const auto height = [&](const glm::dvec3& n) {
        return planet.heightAt(n.x, n.y, n.z) - m_seaLevelM;
    };
    Cross c;
    c.centre = at(point.s, point.t);
    c.sMinus = at(point.s - step, point.t);
    c.sPlus = at(point.s + step, point.t);
    c.tMinus = at(point.s, point.t - step);
    c.tPlus = at(point.s, point.t + step);
    c.h = height(c.centre);
    c.hsMinus = height(c.sMinus);
    c.hsPlus = height(c.sPlus);
    c.htMinus = height(c.tMinus);
    c.htPlus = height(c.tPlus);
    return groundOf(c, moistureAt(c.centre.x, c.centre.y, c.centre.z), level.lostSlopeVariance,
                    level.heightSpreadM);
}

Status PlanetImagery::readTile(const PatchId& id, ImageryTile& out) {
    const int faceLevel = id.level - ManifestGlobe::kLevelOffset;
    const std::int64_t perFace =
        faceLevel >= 0 && faceLevel <= kMaxGlobeFaceLevel ? std::int64_t{1} << faceLevel : 0;
    if (id.level < ManifestGlobe::kLevelOffset || id.level > m_finestLevel || id.x < 0 ||
        id.y < 0 || id.x >= globe::kCubeFaces * perFace || id.y >= perFace)
        return Error{fmt::format(
            "imagery layer \"{}\": tile {}/{}/{} is not one of its tiles "
            "(levels {} … {} of the planet's faces)",
            m_layerName, id.level, id.x, id.y, ManifestGlobe::kLevelOffset, m_finestLevel)};
    const LevelPlanet& level = levelPlanet(faceLevel);
    const ProceduralPlanet& planet = level.planet;
    const int face = static_cast<int>(id.x / perFace);
    const globe::FaceFrame& frame = globe::faceFrame(face);

    // The grid: every stored texel's centre and one more either side, for the differences.
    // Grid index g is stored texel g − 1; s depends on the column alone and t on the row
    // alone, so the tangent adjustment is computed once per column and per row, and each
    // direction is directionOf's arithmetic on them (the same bits).
    constexpr int kGrid = kImageryTileTexels + 2;
    constexpr auto kGridPoints = static_cast<std::size_t>(kGrid) * kGrid;
    m_columnCube.resize(kGrid);
    m_rowCube.resize(kGrid);
    for (int g = 0; g < kGrid; ++g) {
        const double local = imageryPatchLocal(g - 1 + 0.5);
        const globe::FacePoint p = globeImageryPoint(id, local, local);
        m_columnCube[static_cast<std::size_t>(g)] = globe::cubeCoordinate(p.s);
        m_rowCube[static_cast<std::size_t>(g)] = globe::cubeCoordinate(p.t);
    }
    const glm::dvec3 normal(frame.normal), right(frame.right), down(frame.down);
    m_direction.resize(3 * kGridPoints);
    m_height.resize(kGridPoints);
    for (std::size_t r = 0; r < kGrid; ++r) {
        for (std::size_t g = 0; g < kGrid; ++g) {
            const glm::dvec3 cube = normal + m_columnCube[g] * right + m_rowCube[r] * down;
            const glm::dvec3 n =
                cube / std::sqrt(cube.x * cube.x + cube.y * cube.y + cube.z * cube.z);
            const std::size_t i = r * kGrid + g;
            m_direction[3 * i] = n.x;
            m_direction[3 * i + 1] = n.y;
            m_direction[3 * i + 2] = n.z;
            m_height[i] = planet.heightAt(n.x, n.y, n.z) - m_seaLevelM;
        }
    }

    out.id = id;
    out.info = ImageryTileInfo{
        .present = true,
        .presentChildren = static_cast<std::uint8_t>(id.level < m_finestLevel ? 0xF : 0),
        .opaque = true};
    out.rgba.resize(kImageryTileBytes);
    const auto direction = [&](std::size_t i) {
        return glm::dvec3(m_direction[3 * i], m_direction[3 * i + 1], m_direction[3 * i + 2]);
    };
    for (std::size_t r = 1; r + 1 < kGrid; ++r) {
        for (std::size_t g = 1; g + 1 < kGrid; ++g) {
            const std::size_t i = r * kGrid + g;
            const Cross c{.centre = direction(i),
                          .sMinus = direction(i - 1),
                          .sPlus = direction(i + 1),
                          .tMinus = direction(i - kGrid),
                          .tPlus = direction(i + kGrid),
                          .h = m_height[i],
                          .hsMinus = m_height[i - 1],
                          .hsPlus = m_height[i + 1],
                          .htMinus = m_height[i - kGrid],
                          .htPlus = m_height[i + kGrid]};
            const PlanetGround ground = groundOf(c, moistureAt(c.centre.x, c.centre.y, c.centre.z),
                                                 level.lostSlopeVariance, level.heightSpreadM);
            const std::array<float, 3> colour = planetGroundColour(ground);
            std::uint8_t* texel = out.rgba.data() + 4 * ((r - 1) * kImageryTileTexels + (g - 1));
            texel[0] = encodeSrgb(colour[0]);
            texel[1] = encodeSrgb(colour[1]);
            texel[2] = encodeSrgb(colour[2]);
            texel[3] = 255;
        }
    }
    return {};
}

}  // namespace terrain::io
