// ProceduralPlanet: the built-in planet, a height for every direction from the Earth's
// centre, so it is seamless at the poles and across the antimeridian and can be evaluated at
// any resolution, window by window, without a file (issue 20: planet-scale sources without
// terabytes).
//
// The height is a sum of plane waves through 3-D space, evaluated on the unit sphere:
//     H(n) = Σ_k Σ_j a_k · w_k(f_kj · (d_kj · n) + φ_kj)
// with octave k's frequency f_k = f_0 · 2^k (each wave jittered by up to ±20 %), amplitudes
// a_k (ProceduralPlanet.cpp: continents, then mountain ranges), random unit directions d_kj
// and phases φ_kj from the seed. The continents' profile is w = sin; the mountains' is
// w = 2 r − 1 with the ridge r(u) = (√(1 + c²) − √(sin²u + c²)) / (√(1 + c²) − c) ∈ [0, 1]:
// a sharp crest where sin u = 0, a round valley where sin u = ±1. Every term's derivatives
// are bounded in closed form (|r'| ≤ 1, |r''| ≤ 1 / (c (√(1 + c²) − c))),
// so the error of any linear interpolation of H over a triangle is bounded without sampling
// the planet finer (interpolationErrorBound): what lets a pyramid of it be generated patch by
// patch, each with a true Err(P), instead of built bottom-up (io::VirtualPlanetPyramid).
#pragma once

#include "terrain/base/Result.h"

#include <array>
#include <cstddef>
#include <cstdint>

namespace terrain::io {

struct ProceduralPlanetParameters {
    std::uint64_t seed = 1;
};

class ProceduralPlanet {
public:
    static constexpr int kOctaves = 16;        ///< the finest wavelength is about 400 m
    static constexpr int kWavesPerOctave = 4;  ///< directions per octave
    static constexpr std::size_t kWaves = std::size_t{kOctaves} * kWavesPerOctave;

    static ProceduralPlanet create(const ProceduralPlanetParameters& parameters);

    const ProceduralPlanetParameters& parameters() const { return m_parameters; }

    /// Metres above the WGS84 ellipsoid at the unit direction (x, y, z) (an ellipsoid normal,
    /// ECEF axes). The same direction gives the same bits everywhere.
    double heightAt(double x, double y, double z) const;
    /// The same at a geodetic latitude and longitude, degrees.
    double heightAtDegrees(double latitudeDeg, double longitudeDeg) const;

    /// A bound on |H(x) − Σ μ_i H(v_i)| for convex weights μ_i, a point x within `chord` of
    /// each v_i (unit-sphere distances) and its offset from Σ μ_i v_i at most chord²: per
    /// wave min(range, Lipschitz · chord, Hessian · chord² / 6 + Lipschitz · chord²).
    double interpolationErrorBound(double chord) const;

    /// |H| never exceeds this (the sum of the waves' amplitudes), metres.
    double heightBound() const { return m_heightBound; }

    /// The planet seen through a Gaussian footprint of standard deviation `sigma` (unit-sphere
    /// distance ≥ 0): each wave's amplitude times exp(−(f σ)² / 2), the attenuation of a
    /// sine of angular frequency f (3f for a ridge: its profile repeats every half period and
    /// its crest is sharp), and the rest of the wave replaced by its mean. Evaluated by heightAt as
    /// the planet is, so a map of it with texels about 2σ apart (the imagery's colours) shows the
    /// waves it can resolve and not the aliases of those it cannot. lowPassed(0) is the planet.
    ProceduralPlanet lowPassed(double sigma) const;

    /// What lowPassed(sigma) takes away, as variances over the planet: the same everywhere,
    /// as every wave spans the whole planet. A map of the low-passed planet adds them back to
    /// know how much its texels' heights and slopes vary within them.
    struct Roughness {
        double heightVarianceM2 = 0.0;  ///< of the height, m²
        double slopeVariance = 0.0;     ///< of the slope (|∇H| on a sphere of `radiusM`)
    };
    Roughness lostRoughness(double sigma, double radiusM) const;

private:
    /// Wave i's share kept by lowPassed(sigma).
    double keptFraction(std::size_t i, double sigma) const;

    // One array per term, so the evaluation vectorises over the waves.
    struct Waves {
        std::array<double, kWaves> x{}, y{}, z{};  // f · d
        std::array<double, kWaves> phase{};
        std::array<double, kWaves> amplitude{};  // a
        std::array<double, kWaves> frequency{};  // f, per unit of the direction vector
    };
    ProceduralPlanetParameters m_parameters;
    Waves m_waves;
    double m_heightBound = 0.0;
    double m_offset = 0.0;  ///< the damped waves' means (0 unless low-passed)
};

}  // namespace terrain::io
