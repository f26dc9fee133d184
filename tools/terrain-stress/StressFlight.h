// StressFlight: the camera moves of the streaming stress test, a deterministic function of
// a seed: bursts of random teleports, fast low-altitude flight and zoom bursts (dives from
// high above to near the ground), cycling so every phase happens in any run of a few
// seconds. Every pose looks at the DEM, so each frame asks for tiles.
#pragma once

#include "terrain/runtime/Camera.h"
#include "terrain/runtime/TerrainGeometry.h"

#include <cstdint>
#include <functional>
#include <random>
#include <string_view>

namespace terrain::tools {

enum class FlightPhase { Teleport, LowFlight, ZoomBurst, Cruise };
std::string_view flightPhaseName(FlightPhase phase);

/// The stress test's camera moves on either surface (StressFlight on the plane,
/// GlobeStressFlight on the globe): the surface's camera conventions, one frame loop.
class SeededFlight {
public:
    virtual ~SeededFlight() = default;
    /// Instead of the stress phases: a steady flight at `speedMps`, `altitudeM` above the
    /// ground, looking 10° down: the "normal speed" flight streaming latency is measured on.
    virtual void cruise(double speedMps, double altitudeM) = 0;
    /// Advances by `dt` seconds and places `camera` (its viewport is the caller's).
    virtual void step(double dt, runtime::Camera& camera) = 0;
    virtual FlightPhase phase() const = 0;
    virtual std::uint64_t teleports() const = 0;
};

class StressFlight final : public SeededFlight {
public:
    /// `groundHeight(x, y)`: the best known terrain height under a world point (metres).
    StressFlight(const runtime::TerrainGeometry& geometry, std::uint64_t seed,
                 std::function<double(double, double)> groundHeight);

    /// Instead of the stress phases: a steady flight at `speedMps`, `altitudeM` above the
    /// ground, looking 10° down, back and forth along the DEM's diagonal — the "normal
    /// speed" flight that streaming latency is measured on.
    void cruise(double speedMps, double altitudeM) override;

    /// Advances by `dt` seconds and updates `camera` (position and orientation; the
    /// viewport and field of view are the caller's, except during zoom bursts).
    void step(double dt, runtime::Camera& camera) override;

    FlightPhase phase() const override { return m_phase; }
    std::uint64_t teleports() const override { return m_teleports; }

private:
    void startPhase(runtime::Camera& camera);
    void teleport(runtime::Camera& camera);
    glm::dvec2 randomPoint();

    const runtime::TerrainGeometry& m_geometry;
    std::mt19937_64 m_random;
    std::function<double(double, double)> m_groundHeight;
    FlightPhase m_phase = FlightPhase::Teleport;
    double m_phaseLeftS = 0.0;
    double m_nextTeleportS = 0.0;  // within a teleport phase
    double m_heading = 0.0;
    double m_speedMps = 0.0;
    double m_altitudeM = 0.0;  // above ground
    double m_climbMps = 0.0;
    double m_baseFovY = 1.0;
    bool m_cruising = false;
    bool m_cruiseStarted = false;
    std::uint64_t m_teleports = 0;
};

}  // namespace terrain::tools
