#include "terrain/source/ProceduralPlanet.h"

#include "terrain/source/SplitMix64.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace terrain::io {

namespace {

constexpr std::uint64_t kPlanetSalt = 0x504C414E4554ULL;  // "PLANET"

// The continents: the first octaves are plain sines; the ridge profile starts after them.
constexpr int kSmoothOctaves = 3;
constexpr double kContinentAmplitudeM[kSmoothOctaves] = {900.0, 650.0, 450.0};
constexpr double kBaseFrequency = 3.0;  // f_0 per unit direction: a 13,000 km wavelength
// The mountains: octave 3 (1,700 km) at 1,100 m, then a_k ∝ 2^(−h·k) with h = 0.5 down to
// octave 9 (26 km), and smooth below it (h = 1: slopes no steeper at the finest octave,
// 400 m, than at 26 km): ranges of 1–3 km relief.
constexpr double kMountainAmplitudeM = 1100.0;
constexpr int kLastRoughOctave = 9;
constexpr double kRoughness = 0.5;
constexpr double kFineRoughness = 1.0;
constexpr double kFrequencyJitter = 0.2;
constexpr std::size_t kSmoothWaves =
    std::size_t{kSmoothOctaves} * ProceduralPlanet::kWavesPerOctave;

constexpr double kRidgeSoftness = 0.35;  // c
const double kRidgeTop = std::sqrt(1.0 + kRidgeSoftness * kRidgeSoftness);
const double kRidgeSpan = kRidgeTop - kRidgeSoftness;
// Bounds of the profile w(u) = sin u, or w = 2 r(u) − 1, as a function of u. With
// q = √(sin²u + c²) and S = sin²u:
//   |q'| = √(S (1 − S)) / √(S + c²), whose largest value is √(1 + c²) − c (at
//          S = c (√(1 + c²) − c), where c² − S² − 2Sc² = 0), so |w'| ≤ 2;
//   q'' = (c² − S (S + 2c²)) / (S + c²)^(3/2): at most c² / c³ = 1/c where the numerator is
//          positive, and at most (S + c²)² / (S + c²)^(3/2) ≤ √(1 + c²) where it is negative;
//          for c < 0.78 that is |q''| ≤ 1/c, so |w''| ≤ 2 / (c (√(1 + c²) − c)).
constexpr double kRidgeSlope = 2.0;
const double kRidgeCurvature = 2.0 / (kRidgeSoftness * kRidgeSpan);
// |sinOfPhase(u) − sin u| is below this (the series' remainder, the reduction's rounding);
// a profile moves by at most its slope in sin (1 / span for the ridge) times it.
constexpr double kSinError = 1e-9;

double octaveAmplitude(int k) {
    if (k < kSmoothOctaves) return kContinentAmplitudeM[k];
    const int rough = std::min(k, kLastRoughOctave) - kSmoothOctaves;
    const int fine = std::max(k - kLastRoughOctave, 0);
    return kMountainAmplitudeM * std::exp2(-kRoughness * rough - kFineRoughness * fine);
}

// sin u for |u| < 2^40 without a branch or a library call, so the loop over the waves
// vectorises and every sample takes the same instructions (shared edges stay bit-identical):
// u reduced to [−π, π] by the nearest multiple of 2π (rounded with the 1.5 · 2^52 trick),
// folded to [−π/2, π/2], then the Taylor series to x^15 (remainder ≤ (π/2)^17 / 17! ≈ 6e-12).
inline double sinOfPhase(double u) {
    constexpr double kRound = 6755399441055744.0;  // 1.5 · 2^52
    constexpr double kTwoPi = 2.0 * std::numbers::pi;
    const double turns = (u * (1.0 / kTwoPi) + kRound) - kRound;
    const double r = u - turns * kTwoPi;
    // sin(±(π − |r|)) = sin r: min and copysign, so the loop has no branch.
    const double x = std::copysign(std::min(std::fabs(r), std::numbers::pi - std::fabs(r)), r);
    const double x2 = x * x;
    double p = 1.0 / 1307674368000.0;  // 1/15!
    p = p * -x2 + 1.0 / 6227020800.0;  // 1/13!
    p = p * -x2 + 1.0 / 39916800.0;
    p = p * -x2 + 1.0 / 362880.0;
    p = p * -x2 + 1.0 / 5040.0;
    p = p * -x2 + 1.0 / 120.0;
    p = p * -x2 + 1.0 / 6.0;
    p = p * -x2 + 1.0;
    // p = 1 − x²/3! + x⁴/5! − …, alternating from the top: sin x = x · p.
    return x * p;
}

}  // namespace

ProceduralPlanet ProceduralPlanet::create(const ProceduralPlanetParameters& parameters) {
    ProceduralPlanet planet;
    planet.m_parameters = parameters;
    detail::SplitMix64 rng(detail::mix64(parameters.seed ^ kPlanetSalt));
    for (int k = 0; k < kOctaves; ++k) {
        for (int j = 0; j < kWavesPerOctave; ++j) {
            // A uniform direction: z uniform in [−1, 1], the azimuth uniform.
            const double z = rng.uniform(-1.0, 1.0);
            const double azimuth = rng.uniform(0.0, 2.0 * std::numbers::pi);
            const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
            const double frequency = kBaseFrequency * std::ldexp(1.0, k) *
                                     (1.0 + rng.uniform(-kFrequencyJitter, kFrequencyJitter));
            const auto i = static_cast<std::size_t>(k * kWavesPerOctave + j);
            planet.m_waves.x[i] = frequency * r * std::cos(azimuth);
            planet.m_waves.y[i] = frequency * r * std::sin(azimuth);
            planet.m_waves.z[i] = frequency * z;
            planet.m_waves.phase[i] = rng.uniform(0.0, 2.0 * std::numbers::pi);
            planet.m_waves.frequency[i] = frequency;
            // The waves of an octave share its variance.
            planet.m_waves.amplitude[i] = octaveAmplitude(k) * std::sqrt(3.0 / kWavesPerOctave);
            planet.m_heightBound += planet.m_waves.amplitude[i];
        }
    }
    // The sines' error can move every wave a little.
    planet.m_heightBound *= 1.0 + kSinError * kRidgeSlope;
    return planet;
}

double ProceduralPlanet::heightAt(double x, double y, double z) const {
    const Waves& w = m_waves;
    std::array<double, kWaves> s;
    for (std::size_t i = 0; i < kWaves; ++i)
        s[i] = sinOfPhase(w.x[i] * x + w.y[i] * y + w.z[i] * z + w.phase[i]);
    // The ridge: 2 r − 1 with r = (√(1 + c²) − √(sin² + c²)) / (√(1 + c²) − c).
    for (std::size_t i = kSmoothWaves; i < kWaves; ++i)
        s[i] = 2.0 * (kRidgeTop - std::sqrt(s[i] * s[i] + kRidgeSoftness * kRidgeSoftness)) /
                   kRidgeSpan -
               1.0;
    // m_offset is 0 for the planet itself (not low-passed): its heights keep their bits.
    double height = m_offset;
    for (std::size_t i = 0; i < kWaves; ++i) height += w.amplitude[i] * s[i];
    return height;
}

namespace {

// Moments of the ridge profile w = 2 r − 1 over its period π (midpoint sums; smooth and
// periodic, so they converge fast): its mean, its variance and the mean square of w'(u).
struct RidgeMoments {
    double mean = 0.0, variance = 0.0, slopeSquare = 0.0;
};

RidgeMoments ridgeMoments() {
    constexpr int kSteps = 256;
    RidgeMoments m;
    double square = 0.0;
    for (int i = 0; i < kSteps; ++i) {
        const double u = std::numbers::pi * (i + 0.5) / kSteps;
        const double sine = std::sin(u);
        const double q = std::sqrt(sine * sine + kRidgeSoftness * kRidgeSoftness);
        const double w = 2.0 * (kRidgeTop - q) / kRidgeSpan - 1.0;
        const double slope = -2.0 * sine * std::cos(u) / (q * kRidgeSpan);
        m.mean += w;
        square += w * w;
        m.slopeSquare += slope * slope;
    }
    m.mean /= kSteps;
    m.variance = square / kSteps - m.mean * m.mean;
    m.slopeSquare /= kSteps;
    return m;
}

}  // namespace

double ProceduralPlanet::keptFraction(std::size_t i, double sigma) const {
    // A Gaussian's response to a sine of angular frequency f. The ridge's profile repeats
    // every half period, so its fundamental is 2f, and its sharp crest carries harmonics
    // above that: it is damped as a sine of 3f, so that its crests fade before they are
    // sharper than the footprint (damped as 2f, they alias into a hatching).
    const double f = m_waves.frequency[i] * (i >= kSmoothWaves ? 3.0 : 1.0) * sigma;
    return std::exp(-0.5 * f * f);
}

ProceduralPlanet ProceduralPlanet::lowPassed(double sigma) const {
    ProceduralPlanet planet = *this;
    if (!(sigma > 0.0)) return planet;
    const double ridgeMean = ridgeMoments().mean;
    for (std::size_t i = 0; i < kWaves; ++i) {
        const double kept = keptFraction(i, sigma);
        const double a = m_waves.amplitude[i];
        planet.m_waves.amplitude[i] = a * kept;
        if (i >= kSmoothWaves) planet.m_offset += a * (1.0 - kept) * ridgeMean;
    }
    return planet;
}

ProceduralPlanet::Roughness ProceduralPlanet::lostRoughness(double sigma, double radiusM) const {
    Roughness lost;
    if (!(sigma > 0.0)) return lost;
    const RidgeMoments ridge = ridgeMoments();
    for (std::size_t i = 0; i < kWaves; ++i) {
        const double kept = keptFraction(i, sigma);
        const double a = m_waves.amplitude[i];
        // A wave's energy at a frequency the filter passes by `kept` is lost by 1 − kept².
        const double lostShare = 1.0 - kept * kept;
        const bool isRidge = i >= kSmoothWaves;
        lost.heightVarianceM2 += a * a * (isRidge ? ridge.variance : 0.5) * lostShare;
        // |∇| on the sphere: a w'(u) f |d⊥| / R, where |d⊥|² averages 2/3 over directions.
        const double f = m_waves.frequency[i] / radiusM;
        lost.slopeVariance +=
            a * a * f * f * (isRidge ? ridge.slopeSquare : 0.5) * (2.0 / 3.0) * lostShare;
    }
    return lost;
}

double ProceduralPlanet::heightAtDegrees(double latitudeDeg, double longitudeDeg) const {
    const double lat = latitudeDeg * (std::numbers::pi / 180.0);
    const double lon = longitudeDeg * (std::numbers::pi / 180.0);
    return heightAt(std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon), std::sin(lat));
}

double ProceduralPlanet::interpolationErrorBound(double chord) const {
    // For one wave g with |∇g| ≤ K and |∇²g| ≤ M (the profile's bounds times f and f²):
    // Σ μ_i g(v_i) = g(y) + Σ μ_i ρ_i with y = Σ μ_i v_i and |ρ_i| ≤ M |v_i − y|² / 2 (Taylor
    // about y, where the linear terms cancel). Σ μ_i |v_i − y|² = R² − |y − c|² for the
    // circumcentre c and radius R, at most ℓ²/3 for a triangle whose longest side is ℓ ≤ chord
    // (R ≤ ℓ/√3 if it is acute; else the largest value is on the longest side, (ℓ/2)²). With
    // |g(x) − g(y)| ≤ K |x − y| ≤ K chord²: M chord² / 6 + K chord². Also
    // |g(x) − Σ μ_i g(v_i)| ≤ Σ μ_i K |x − v_i| ≤ K chord, and never more than the wave's
    // range. Interpolation is linear, so the waves' bounds add up. The computed sines differ
    // from sin by < kSinError, which can add twice its effect.
    double bound = 0.0;
    for (std::size_t i = 0; i < kWaves; ++i) {
        const double a = m_waves.amplitude[i];
        const double f = m_waves.frequency[i];
        const double slope = i < kSmoothWaves ? 1.0 : kRidgeSlope;
        const double curvature = i < kSmoothWaves ? 1.0 : kRidgeCurvature;
        const double k = a * slope * f;
        const double m = a * curvature * f * f;
        bound += std::min({2.0 * a, k * chord, m * chord * chord / 6.0 + k * chord * chord}) +
                 2.0 * a * slope * kSinError;
    }
    return bound;
}

}  // namespace terrain::io
