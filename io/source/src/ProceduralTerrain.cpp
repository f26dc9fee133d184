// The procedural DEM: relief (hills + Musgrave's ridged multifractal mountains), then
// the fault, the mesas and the lake, then the spikes, all quantised to 1/1024 m.
#include "terrain/source/ProceduralTerrain.h"

#include "GradientNoise.h"
#include "terrain/source/SplitMix64.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <thread>
#include <utility>

namespace terrain::io {

// Buffers of one row's evaluation; one per thread, reused from row to row.
struct ProceduralTerrain::RowScratch {
    detail::NoiseRowScratch lattice;
    std::vector<double> noise, weight, ridged, hills, mask, base, discDistance;
};

namespace {

constexpr int kMaxPlateaus = 16;
constexpr int kMaxSpikes = 4096;
constexpr double kLakeWarp = 0.3;        // shoreline wobble, in lake radii
constexpr double kLakeShoreRadii = 1.5;  // width of the plains that rise from the water
constexpr double kPlateauWarp = 0.25;    // mesa outline wobble, in mesa radii
constexpr int kPlacementTries = 64;

// Salts keep the noise fields of one seed independent of each other.
constexpr std::uint64_t kRidgedSalt = 0x52494447ULL;  // "RIDG"
constexpr std::uint64_t kHillSalt = 0x48494C4CULL;    // "HILL"
constexpr std::uint64_t kMaskSalt = 0x4D41534BULL;    // "MASK"
constexpr std::uint64_t kDiscSalt = 0x44495343ULL;    // "DISC"
constexpr std::uint64_t kPlaceSalt = 0x504C4143ULL;   // "PLAC"

double quantise(double heightM) {
    return std::floor(heightM * 1024.0 + 0.5) * ProceduralTerrain::kHeightQuantumM;
}

double smoothstep(double edge0, double edge1, double v) {
    const double t = std::clamp((v - edge0) / (edge1 - edge0), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

bool finiteAtLeast(double v, double lo) { return std::isfinite(v) && v >= lo; }

}  // namespace

// ---------------------------------------------------------------------------------------
// Construction

Result<ProceduralTerrain> ProceduralTerrain::create(const ProceduralTerrainParameters& p) {
    const auto fail = [](std::string what) {
        return Error{fmt::format("procedural terrain: {}", what)};
    };
    for (const auto& [name, side] :
         {std::pair{"widthSamples", p.widthSamples}, std::pair{"heightSamples", p.heightSamples}}) {
        if (side < kMinSideSamples || side > kMaxSideSamples)
            return fail(fmt::format("{} = {} is outside [{}, {}]", name, side, kMinSideSamples,
                                    kMaxSideSamples));
    }
    if (!std::isfinite(p.sampleSpacingM) || p.sampleSpacingM <= 0.0)
        return fail(fmt::format("sampleSpacingM = {} must be a positive number", p.sampleSpacingM));
    for (const auto& [name, v] :
         {std::pair{"hillHeightM", p.hillHeightM}, std::pair{"mountainHeightM", p.mountainHeightM},
          std::pair{"cliffHeightM", p.cliffHeightM}, std::pair{"plateauHeightM", p.plateauHeightM},
          std::pair{"spikeHeightM", p.spikeHeightM}, std::pair{"ridgeGain", p.ridgeGain},
          std::pair{"roughness", p.roughness}, std::pair{"lakeRadius", p.lakeRadius},
          std::pair{"plateauRadius", p.plateauRadius}}) {
        if (!finiteAtLeast(v, 0.0))
            return fail(fmt::format("{} = {} must be a number ≥ 0", name, v));
    }
    if (!std::isfinite(p.ridgeOffset) || p.ridgeOffset <= 0.0)
        return fail(fmt::format("ridgeOffset = {} must be a positive number", p.ridgeOffset));
    if (p.roughness > 3.0) return fail(fmt::format("roughness = {} exceeds 3", p.roughness));
    if (p.lakeRadius > 0.25 || p.plateauRadius > 0.25)
        return fail("lakeRadius and plateauRadius are fractions of the DEM and must be ≤ 0.25");
    if (p.octaves < 0 || p.octaves > kMaxOctaves)
        return fail(
            fmt::format("octaves = {} is outside [0, {}] (0 = automatic)", p.octaves, kMaxOctaves));
    if (p.plateauCount < 0 || p.plateauCount > kMaxPlateaus)
        return fail(
            fmt::format("plateauCount = {} is outside [0, {}]", p.plateauCount, kMaxPlateaus));
    if (p.plateauSideSamples < 1 || p.plateauSideSamples > 1024)
        return fail(
            fmt::format("plateauSideSamples = {} is outside [1, 1024]", p.plateauSideSamples));
    if (p.spikeCount < 0 || p.spikeCount > kMaxSpikes)
        return fail(fmt::format("spikeCount = {} is outside [0, {}]", p.spikeCount, kMaxSpikes));

    ProceduralTerrain terrain;
    terrain.m_parameters = p;
    terrain.m_unitSamples = static_cast<double>(std::min(p.widthSamples, p.heightSamples) - 1);
    const double unit = terrain.m_unitSamples;
    if (!std::isfinite(p.mountainFrequency) || p.mountainFrequency <= 0.0 ||
        unit / p.mountainFrequency < 2.0)
        return fail(
            fmt::format("mountainFrequency = {} must be positive and leave a wavelength "
                        "of at least 2 samples",
                        p.mountainFrequency));

    // Every height ≤ hills + mountains + cliff + mesa + spike (each term's own bound).
    terrain.m_heightBoundM = p.hillHeightM + std::max(p.mountainHeightM, 0.5 * p.hillHeightM) +
                             p.cliffHeightM + p.plateauHeightM + p.spikeHeightM;
    if (terrain.m_heightBoundM >= kExactHeightLimitM)
        return fail(fmt::format(
            "heights could reach {} m (hill + mountain + cliff + plateau + spike heights); keep "
            "the sum below {} m so that every height is an exact float",
            terrain.m_heightBoundM, kExactHeightLimitM));

    // Octave k: 2^k · mountainFrequency cycles per unit, shifted by its own offset.
    // Drawn from the seed alone, so the first octaves are the same whatever the DEM size.
    detail::SplitMix64 rng(detail::mix64(p.seed ^ kRidgedSalt));
    const auto makeOctave = [&](double cyclesPerUnit, std::uint64_t salt) {
        Octave o;
        o.scale = cyclesPerUnit / unit;
        o.offsetX = rng.uniform(0.0, 256.0);
        o.offsetY = rng.uniform(0.0, 256.0);
        o.salt = detail::mix64(p.seed ^ salt ^ rng.next());
        return o;
    };
    int octaves = p.octaves;
    if (octaves == 0) {
        // Add octaves while their wavelength is at least two samples.
        octaves = 1;
        while (octaves < kMaxOctaves &&
               unit / (p.mountainFrequency * std::ldexp(1.0, octaves)) >= 2.0)
            ++octaves;
    }
    // Musgrave's exponent array: amplitude of octave i = lacunarity^(−i·H), lacunarity 2.
    const double gainPerOctave = std::exp2(-p.roughness);
    double amplitude = 1.0;
    double amplitudeSum = 0.0;
    std::array<Octave, kMaxOctaves> all{};
    for (int k = 0; k < kMaxOctaves; ++k) {
        all[k] = makeOctave(p.mountainFrequency * std::ldexp(1.0, k), kRidgedSalt + k);
        all[k].amplitude = amplitude;
        if (k < octaves) amplitudeSum += amplitude;
        amplitude *= gainPerOctave;
    }
    terrain.m_ridgedOctaves.assign(all.begin(), all.begin() + octaves);
    // (offset − |n|)² ≤ max(offset, |offset − 1|)² for |n| ≤ 1, and every weight ≤ 1.
    const double signalBound = std::max(p.ridgeOffset, std::abs(p.ridgeOffset - 1.0));
    terrain.m_ridgedScale = 1.0 / (signalBound * signalBound * amplitudeSum);
    for (std::size_t k = 0; k < terrain.m_hillOctaves.size(); ++k)
        terrain.m_hillOctaves[k] =
            makeOctave(1.0 * std::ldexp(1.0, static_cast<int>(k)), kHillSalt + k);
    for (std::size_t k = 0; k < terrain.m_maskOctaves.size(); ++k)
        terrain.m_maskOctaves[k] =
            makeOctave(1.5 * std::ldexp(1.0, static_cast<int>(k)), kMaskSalt + k);
    terrain.m_cliffHeightM = quantise(p.cliffHeightM);

    if (Status placed = terrain.placeFeatures(); !placed) return placed.error();
    return terrain;
}

Status ProceduralTerrain::placeFeatures() {
    const ProceduralTerrainParameters& p = m_parameters;
    const double lastX = static_cast<double>(p.widthSamples - 1);
    const double lastY = static_cast<double>(p.heightSamples - 1);
    detail::SplitMix64 rng(detail::mix64(p.seed ^ kPlaceSalt));

    // The fault runs from the north edge to the south edge east of the middle (at 52 % to
    // 80 % of the width), so the west (high) block is the larger.
    const double topU = rng.uniform(0.60, 0.72);
    const double bottomU = topU + rng.uniform(-0.08, 0.08);
    if (hasCliff()) {
        m_cliffColumnAtTop = topU * lastX;
        m_cliffColumnsPerRow = (bottomU - topU) * lastX / lastY;
    }

    const auto clipToDem = [&](SampleBox box) {
        box.minX = std::max<std::int64_t>(box.minX, 0);
        box.minY = std::max<std::int64_t>(box.minY, 0);
        box.maxX = std::min(box.maxX, p.widthSamples - 1);
        box.maxY = std::min(box.maxY, p.heightSamples - 1);
        return box;
    };
    const auto boxAround = [](double cx, double cy, double reach) {
        return SampleBox{static_cast<std::int64_t>(std::floor(cx - reach)),
                         static_cast<std::int64_t>(std::floor(cy - reach)),
                         static_cast<std::int64_t>(std::ceil(cx + reach)),
                         static_cast<std::int64_t>(std::ceil(cy + reach))};
    };
    const auto insideDem = [&](const SampleBox& box) {
        return box.minX >= 1 && box.minY >= 1 && box.maxX <= p.widthSamples - 2 &&
               box.maxY <= p.heightSamples - 2;
    };
    const auto overlaps = [](const SampleBox& a, const SampleBox& b, std::int64_t margin) {
        return a.minX - margin <= b.maxX && b.minX - margin <= a.maxX &&
               a.minY - margin <= b.maxY && b.minY - margin <= a.maxY;
    };
    const auto freeOfDiscs = [&](const SampleBox& box, std::int64_t margin) {
        return std::none_of(m_discs.begin(), m_discs.end(), [&](const WarpedDisc& d) {
            return overlaps(box, d.influence, margin);
        });
    };
    const auto makeDisc = [&](double cx, double cy, double radius, double warp, double rim,
                              std::uint64_t salt) {
        WarpedDisc disc;
        disc.centreX = cx;
        disc.centreY = cy;
        disc.radius = radius;
        disc.warp = warp;
        disc.rimSamples = rim;
        // Outline wobble: about three bumps across the radius, in the DEM's own units.
        disc.warpNoise.scale = 1.5 / radius;
        disc.warpNoise.offsetX = rng.uniform(0.0, 256.0);
        disc.warpNoise.offsetY = rng.uniform(0.0, 256.0);
        disc.warpNoise.salt = detail::mix64(p.seed ^ kDiscSalt ^ salt);
        // d ≤ 1 + rim/radius needs |p − c| ≤ radius·(1 + warp) + rim.
        disc.influence = boxAround(cx, cy, radius * (1.0 + warp) + rim + 1.0);
        return disc;
    };

    // The lake first: it is the largest and the hardest to fit.
    std::vector<WarpedDisc> mesas;
    if (p.lakeRadius > 0.0) {
        const double radius = p.lakeRadius * m_unitSamples;
        for (int attempt = 0; attempt < kPlacementTries; ++attempt) {
            const double cx = rng.uniform(0.1, 0.9) * lastX;
            const double cy = rng.uniform(0.1, 0.9) * lastY;
            WarpedDisc disc =
                makeDisc(cx, cy, radius, kLakeWarp, kLakeShoreRadii * radius, 0x4C414B45ULL);
            if (!insideDem(disc.influence) || touchesCliff(disc.influence, 2)) continue;
            // The water lies at the lowest land around it, so the plains rise from it.
            double lowest = std::numeric_limits<double>::infinity();
            const SampleBox& box = disc.influence;
            for (int j = 0; j <= 16; ++j) {
                for (int i = 0; i <= 16; ++i) {
                    const std::int64_t x = box.minX + (box.maxX - box.minX) * i / 16;
                    const std::int64_t y = box.minY + (box.maxY - box.minY) * j / 16;
                    lowest = std::min(lowest, heightBeforeFeatures(x, y));
                }
            }
            disc.level = quantise(lowest);
            TerrainLake lake;
            lake.centreX = cx;
            lake.centreY = cy;
            lake.radiusSamples = radius;
            lake.levelM = static_cast<float>(disc.level);
            lake.bounds = clipToDem(boxAround(cx, cy, radius * (1.0 + kLakeWarp) + 1.0));
            m_lake = lake;
            m_discs.push_back(disc);
            break;
        }
    }

    // Mesas: anywhere clear of the fault, the lake and each other.
    if (p.plateauRadius > 0.0) {
        const double radius = p.plateauRadius * m_unitSamples;
        for (int i = 0; i < p.plateauCount; ++i) {
            for (int attempt = 0; attempt < kPlacementTries; ++attempt) {
                const double cx = rng.uniform(0.05, 0.95) * lastX;
                const double cy = rng.uniform(0.05, 0.95) * lastY;
                WarpedDisc disc = makeDisc(cx, cy, radius, kPlateauWarp,
                                           static_cast<double>(p.plateauSideSamples),
                                           0x4D455341ULL + static_cast<std::uint64_t>(i));
                if (!insideDem(disc.influence) || touchesCliff(disc.influence, 2) ||
                    !freeOfDiscs(disc.influence, 2))
                    continue;
                const auto centreX = static_cast<std::int64_t>(std::llround(cx));
                const auto centreY = static_cast<std::int64_t>(std::llround(cy));
                disc.level = quantise(heightBeforeFeatures(centreX, centreY) + p.plateauHeightM);
                TerrainPlateau plateau;
                plateau.centreX = cx;
                plateau.centreY = cy;
                plateau.radiusSamples = radius;
                plateau.topHeightM = static_cast<float>(disc.level);
                plateau.topBounds =
                    clipToDem(boxAround(cx, cy, radius * (1.0 + kPlateauWarp) + 1.0));
                m_plateaus.push_back(plateau);
                mesas.push_back(disc);
                m_discs.push_back(disc);
                break;
            }
        }
    }
    // evaluateRow applies the mesas before the lake; keep m_discs in that order too.
    if (m_lake) {
        WarpedDisc lakeDisc = m_discs.front();
        m_discs = mesas;
        m_discs.push_back(lakeDisc);
    }

    // Spikes: snapped to samples, their 5×5 neighbourhoods clear of the fault, the lake,
    // the mesas and each other, so each is a lone sample above plain terrain.
    // They are collected apart from m_spikes, which evaluateRow reads and needs sorted.
    const double spikeHeight = quantise(p.spikeHeightM);
    std::vector<TerrainSpike> spikes;
    for (int attempt = 0;
         attempt < p.spikeCount * kPlacementTries && static_cast<int>(spikes.size()) < p.spikeCount;
         ++attempt) {
        const auto x = static_cast<std::int64_t>(std::llround(rng.uniform(0.02, 0.98) * lastX));
        const auto y = static_cast<std::int64_t>(std::llround(rng.uniform(0.02, 0.98) * lastY));
        const SampleBox box{x - 2, y - 2, x + 2, y + 2};
        if (!insideDem(box) || touchesCliff(box, 1) || !freeOfDiscs(box, 1)) continue;
        const bool crowded = std::any_of(spikes.begin(), spikes.end(), [&](const auto& s) {
            return std::max(std::abs(s.x - x), std::abs(s.y - y)) < 4;
        });
        if (crowded) continue;
        double highestNeighbour = -std::numeric_limits<double>::infinity();
        for (std::int64_t dy = -1; dy <= 1; ++dy) {
            for (std::int64_t dx = -1; dx <= 1; ++dx) {
                if (dx == 0 && dy == 0) continue;
                highestNeighbour =
                    std::max(highestNeighbour, static_cast<double>(evaluateSample(x + dx, y + dy)));
            }
        }
        // Both terms are multiples of 1/1024 below 8192: the sum is exact.
        spikes.push_back(TerrainSpike{x, y, static_cast<float>(highestNeighbour + spikeHeight),
                                      static_cast<float>(spikeHeight)});
    }
    m_spikes = std::move(spikes);
    std::sort(m_spikes.begin(), m_spikes.end(), [](const TerrainSpike& a, const TerrainSpike& b) {
        return a.y != b.y ? a.y < b.y : a.x < b.x;
    });
    return {};
}

// ---------------------------------------------------------------------------------------
// Evaluation

std::int64_t ProceduralTerrain::cliffColumn(std::int64_t y) const {
    if (!hasCliff()) return width() - 1;
    const std::int64_t column =
        detail::floorToInt(m_cliffColumnAtTop + m_cliffColumnsPerRow * static_cast<double>(y));
    return std::clamp<std::int64_t>(column, 0, width() - 2);
}

bool ProceduralTerrain::touchesCliff(const SampleBox& box, std::int64_t margin) const {
    if (!hasCliff()) return false;
    // The fault changes columns cliffColumn(y) and cliffColumn(y) + 1; it is monotonic in
    // y, so the box's first and last rows bound it.
    const std::int64_t a =
        cliffColumn(std::clamp<std::int64_t>(box.minY - margin, 0, height() - 1));
    const std::int64_t b =
        cliffColumn(std::clamp<std::int64_t>(box.maxY + margin, 0, height() - 1));
    const std::int64_t lo = std::min(a, b) - margin;
    const std::int64_t hi = std::max(a, b) + 1 + margin;
    return lo <= box.maxX && box.minX <= hi;
}

namespace {

detail::NoiseField fieldOf(double scale, double offsetX, double offsetY, std::uint64_t salt) {
    return detail::NoiseField{scale, offsetX, offsetY, salt};
}

}  // namespace

void ProceduralTerrain::baseRow(std::int64_t y, std::int64_t xStart, std::size_t count,
                                RowScratch& scratch) const {
    for (std::vector<double>* v : {&scratch.noise, &scratch.weight, &scratch.ridged, &scratch.hills,
                                   &scratch.mask, &scratch.base})
        v->resize(count);
    double* noise = scratch.noise.data();
    const auto octaveRow = [&](const Octave& o) {
        detail::noiseRow(fieldOf(o.scale, o.offsetX, o.offsetY, o.salt), y, xStart, count, noise,
                         scratch.lattice);
    };

    // Musgrave's ridged multifractal (F. K. Musgrave, "Texturing & Modeling: A Procedural
    // Approach", 3rd ed., ch. 16, RidgedMultifractal()): each octave's ridges are
    // (offset − |noise|)², weighted by the previous octave's weighted signal × gain so
    // detail gathers on the ridges and valleys stay smooth; normalised to [0, 1].
    // Musgrave's early exit (weight < 0.001) is left out: it leaves small steps where it
    // triggers. Octave by octave over the whole row, so the inner loops vectorise.
    double* weight = scratch.weight.data();
    double* ridged = scratch.ridged.data();
    std::fill_n(weight, count, 1.0);
    std::fill_n(ridged, count, 0.0);
    const double offset = m_parameters.ridgeOffset;
    const double gain = m_parameters.ridgeGain;
    for (const Octave& o : m_ridgedOctaves) {
        octaveRow(o);
        const double amplitude = o.amplitude;
        for (std::size_t i = 0; i < count; ++i) {
            double signal = offset - std::abs(noise[i]);
            signal *= signal;
            signal *= weight[i];
            ridged[i] += signal * amplitude;
            weight[i] = std::clamp(signal * gain, 0.0, 1.0);
        }
    }

    // Hills: three octaves of fBm in [−1, 1]. Mountain mask: two octaves, 0 on the plains.
    double* hills = scratch.hills.data();
    double* mask = scratch.mask.data();
    std::fill_n(hills, count, 0.0);
    std::fill_n(mask, count, 0.0);
    constexpr std::array<double, 3> kHillWeights{1.0 / 1.75, 0.5 / 1.75, 0.25 / 1.75};
    for (std::size_t k = 0; k < m_hillOctaves.size(); ++k) {
        octaveRow(m_hillOctaves[k]);
        for (std::size_t i = 0; i < count; ++i) hills[i] += kHillWeights[k] * noise[i];
    }
    constexpr std::array<double, 2> kMaskWeights{1.0 / 1.5, 0.5 / 1.5};
    for (std::size_t k = 0; k < m_maskOctaves.size(); ++k) {
        octaveRow(m_maskOctaves[k]);
        for (std::size_t i = 0; i < count; ++i) mask[i] += kMaskWeights[k] * noise[i];
    }

    // The ridged detail runs everywhere (the plains get it at the hills' scale), so every
    // octave down to the sample spacing shows.
    const double hillH = m_parameters.hillHeightM;
    const double mountainH = m_parameters.mountainHeightM;
    double* base = scratch.base.data();
    for (std::size_t i = 0; i < count; ++i) {
        const double m = smoothstep(-0.25, 0.35, mask[i]);
        const double relief = mountainH * m + 0.5 * hillH * (1.0 - m);
        base[i] = 0.5 * hillH * (1.0 + hills[i]) + relief * (ridged[i] * m_ridgedScale);
    }
}

void ProceduralTerrain::discDistances(const WarpedDisc& disc, std::int64_t y, std::int64_t xStart,
                                      std::size_t count, RowScratch& scratch) const {
    scratch.discDistance.resize(count);
    double* d = scratch.discDistance.data();
    const Octave& o = disc.warpNoise;
    detail::noiseRow(fieldOf(o.scale, o.offsetX, o.offsetY, o.salt), y, xStart, count, d,
                     scratch.lattice);
    const double dy = static_cast<double>(y) - disc.centreY;
    for (std::size_t i = 0; i < count; ++i) {
        const double dx = static_cast<double>(xStart + static_cast<std::int64_t>(i)) - disc.centreX;
        const double wobble = std::clamp(d[i], -1.0, 1.0);
        d[i] = std::sqrt(dx * dx + dy * dy) / disc.radius + disc.warp * wobble;
    }
}

bool ProceduralTerrain::insideDisc(const WarpedDisc& disc, std::int64_t x, std::int64_t y) const {
    RowScratch scratch;
    discDistances(disc, y, x, 1, scratch);
    return scratch.discDistance[0] <= 1.0;
}

double ProceduralTerrain::heightBeforeFeatures(std::int64_t x, std::int64_t y) const {
    RowScratch scratch;
    const bool west = x <= cliffColumn(y);
    baseRow(y, west ? x : x - 1, 1, scratch);
    return quantise(scratch.base[0]) + (west ? m_cliffHeightM : 0.0);
}

void ProceduralTerrain::evaluateRow(std::int64_t y, std::int64_t x0, std::int64_t count, float* out,
                                    RowScratch& scratch) const {
    // The fault: the east block is the relief shifted one column east, so sample
    // (cliff + 1) repeats the relief of sample (cliff) and the two differ by exactly the
    // cliff height (both quantised, so the float difference is exact too).
    const std::int64_t cliff = cliffColumn(y);
    const bool anyEast = x0 + count - 1 > cliff;
    const std::int64_t baseStart = anyEast ? x0 - 1 : x0;
    baseRow(y, baseStart, static_cast<std::size_t>(x0 + count - baseStart), scratch);
    const double* base = scratch.base.data();
    for (std::int64_t i = 0; i < count; ++i) {
        const std::int64_t x = x0 + i;
        const bool west = x <= cliff;
        const std::int64_t reliefColumn = west ? x : x - 1;
        out[i] = static_cast<float>(quantise(base[reliefColumn - baseStart]) +
                                    (west ? m_cliffHeightM : 0.0));
    }

    // Mesas and the lake, over the part of the row each one touches.
    for (const WarpedDisc& disc : m_discs) {
        const SampleBox& box = disc.influence;
        if (y < box.minY || y > box.maxY) continue;
        const std::int64_t from = std::max(x0, box.minX);
        const std::int64_t to = std::min(x0 + count - 1, box.maxX);
        if (from > to) continue;
        discDistances(disc, y, from, static_cast<std::size_t>(to - from + 1), scratch);
        for (std::int64_t x = from; x <= to; ++x) {
            const double d = scratch.discDistance[static_cast<std::size_t>(x - from)];
            float& h = out[x - x0];
            if (d <= 1.0) {
                h = static_cast<float>(disc.level);  // exact: the lake surface, the mesa top
            } else {
                const double beyondRim = (d - 1.0) * disc.radius;
                if (beyondRim < disc.rimSamples) {
                    const double t = smoothstep(0.0, 1.0, beyondRim / disc.rimSamples);
                    h = static_cast<float>(
                        quantise(disc.level + t * (static_cast<double>(h) - disc.level)));
                }
            }
        }
    }

    const auto first =
        std::lower_bound(m_spikes.begin(), m_spikes.end(), y,
                         [](const TerrainSpike& s, std::int64_t row) { return s.y < row; });
    for (auto s = first; s != m_spikes.end() && s->y == y; ++s) {
        if (s->x >= x0 && s->x < x0 + count) out[s->x - x0] = s->heightM;
    }
}

float ProceduralTerrain::evaluateSample(std::int64_t x, std::int64_t y) const {
    RowScratch scratch;
    float h = 0.0F;
    evaluateRow(y, x, 1, &h, scratch);
    return h;
}

float ProceduralTerrain::sample(std::int64_t x, std::int64_t y) const {
    TERRAIN_ASSERT(x >= 0 && x < width() && y >= 0 && y < height(), "sample outside the DEM");
    return evaluateSample(x, y);
}

void ProceduralTerrain::fillWindow(std::int64_t x0, std::int64_t y0, std::int64_t windowWidth,
                                   std::int64_t windowHeight, std::span<float> out,
                                   unsigned threadCount) const {
    TERRAIN_ASSERT(windowWidth >= 0 && windowHeight >= 0, "negative window size");
    TERRAIN_ASSERT(
        x0 >= 0 && y0 >= 0 && x0 <= width() - windowWidth && y0 <= height() - windowHeight,
        "window outside the DEM");
    TERRAIN_ASSERT(
        static_cast<std::uint64_t>(out.size()) ==
            static_cast<std::uint64_t>(windowWidth) * static_cast<std::uint64_t>(windowHeight),
        "output span does not match the window");
    if (windowWidth == 0 || windowHeight == 0) return;
    const auto rows = [&](std::int64_t firstRow, std::int64_t endRow) {
        RowScratch scratch;
        for (std::int64_t r = firstRow; r < endRow; ++r)
            evaluateRow(y0 + r, x0, windowWidth, out.data() + r * windowWidth, scratch);
    };
    if (threadCount == 0) threadCount = std::max(1U, std::thread::hardware_concurrency());
    // Rows are independent and each is computed whole by one thread, so the result is
    // the same for every thread count.
    const std::int64_t threads = std::min<std::int64_t>(threadCount, windowHeight);
    if (threads <= 1) {
        rows(0, windowHeight);
        return;
    }
    std::vector<std::thread> workers;
    workers.reserve(static_cast<std::size_t>(threads - 1));
    const auto chunkStart = [&](std::int64_t t) { return windowHeight * t / threads; };
    for (std::int64_t t = 1; t < threads; ++t)
        workers.emplace_back(rows, chunkStart(t), chunkStart(t + 1));
    rows(0, chunkStart(1));
    for (std::thread& worker : workers) worker.join();
}

Georeference ProceduralTerrain::windowGeoreference(std::int64_t x0, std::int64_t y0,
                                                   int epsg) const {
    const double s = m_parameters.sampleSpacingM;
    Georeference geo;
    geo.originX = static_cast<double>(x0) * s;
    geo.originY = static_cast<double>(height() - y0) * s;
    geo.pixelSizeX = s;
    geo.pixelSizeY = s;
    geo.epsg = epsg;
    return geo;
}

// ---------------------------------------------------------------------------------------
// Feature queries

bool ProceduralTerrain::isLake(std::int64_t x, std::int64_t y) const {
    // The lake is the last disc (evaluateRow applies it after the mesas).
    return m_lake && m_lake->bounds.contains(x, y) && insideDisc(m_discs.back(), x, y);
}

std::optional<std::size_t> ProceduralTerrain::plateauTopAt(std::int64_t x, std::int64_t y) const {
    for (std::size_t i = 0; i < m_plateaus.size(); ++i) {
        if (m_plateaus[i].topBounds.contains(x, y) && insideDisc(m_discs[i], x, y)) return i;
    }
    return std::nullopt;
}

}  // namespace terrain::io
