// GlobeStressFlight: StressFlight's camera moves on a globe, a deterministic function of a
// seed (and the frame times), every pose looking at the planet: bursts of teleports (mostly over
// the data, some anywhere on the planet, from a few samples above the ground to 20,000 km), fast
// flight a few samples above the ground over the data, and dives from orbit to the ground within a
// couple of seconds, cycling so every phase happens in any run of a few seconds. Or, for latency
// measurements, a steady cruise.
#pragma once

#include "StressFlight.h"

#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/GlobeCamera.h"

#include <cstdint>
#include <functional>
#include <random>

namespace terrain::tools {

class GlobeStressFlight final : public SeededFlight {
public:
    /// `groundHeight(pose)`: the best known height at or above the ground under a pose
    /// (metres above the ellipsoid).
    GlobeStressFlight(const io::PyramidManifest& manifest, std::uint64_t seed,
                      std::function<double(const runtime::GlobePose&)> groundHeight);

    /// Instead of the stress phases: a steady flight at `speedMps`, `altitudeM` above the
    /// ground, looking 10° down, back and forth across the data's extent.
    void cruise(double speedMps, double altitudeM) override;

    /// Advances by `dt` seconds and places `camera` (its field of view is the caller's).
    void step(double dt, runtime::Camera& camera) override;

    FlightPhase phase() const override { return m_phase; }
    std::uint64_t teleports() const override { return m_teleports; }

private:
    void startPhase();
    void teleport();
    globe::Geodetic randomPlaceInData();
    double aboveGround(double altitudeM) const;

    std::mt19937_64 m_random;
    std::function<double(const runtime::GlobePose&)> m_groundHeight;
    double m_west = 0.0, m_south = 0.0, m_spanLon = 0.0, m_spanLat = 0.0;  // the data, degrees
    double m_extentM = 0.0;                                                // its larger side
    double m_spacingM = 0.0;  // the finest level's sample spacing
    runtime::GlobePose m_pose;
    FlightPhase m_phase = FlightPhase::Teleport;
    double m_phaseLeftS = 0.0;
    double m_nextTeleportS = 0.0;
    double m_speedMps = 0.0;
    double m_altitudeM = 0.0;  // above the ground
    double m_diveRatePerS = 0.0;
    double m_divePitchDeg = -90.0;
    bool m_cruising = false;
    std::uint64_t m_teleports = 0;
};

}  // namespace terrain::tools
