// GlobeStressFlight: phases of 1–3 s over the data's extent (the finest source's, from the
// manifest); speeds and heights scale with that extent and the finest sample spacing, as
// StressFlight's do with a planar DEM's.
#include "GlobeStressFlight.h"

#include "terrain/globe/GlobePatch.h"
#include "terrain/runtime/GlobeController.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace terrain::tools {
namespace {

constexpr double kDegree = std::numbers::pi / 180.0;
constexpr double kOrbitM = 20e6;

// How far below the horizontal the Earth's limb lies seen from `heightM`: a view pitched at
// least this far down looks at the planet, not past it.
double horizonDipDeg(double heightM) {
    const double r = globe::Wgs84::kEquatorialRadius;
    return std::acos(r / (r + std::max(heightM, 0.0))) / kDegree;
}

}  // namespace

GlobeStressFlight::GlobeStressFlight(const io::PyramidManifest& manifest, std::uint64_t seed,
                                     std::function<double(const runtime::GlobePose&)> groundHeight)
    : m_random(seed), m_groundHeight(std::move(groundHeight)) {
    const io::ManifestGlobe& g = *manifest.globe;
    m_west = g.west;
    m_south = g.south;
    m_spanLon = g.east >= g.west ? g.east - g.west : g.east + 360.0 - g.west;
    m_spanLat = g.north - g.south;
    const double centreLat = g.south + 0.5 * m_spanLat;
    m_extentM = std::max(m_spanLat, m_spanLon * std::cos(centreLat * kDegree)) * kDegree *
                globe::Wgs84::kEquatorialRadius;
    m_spacingM = globe::maxSampleSpacing(g.faceFinestLevel, manifest.layout.patchQuads());
    m_extentM = std::max(m_extentM, 4.0 * m_spacingM);
}

globe::Geodetic GlobeStressFlight::randomPlaceInData() {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const double lat = m_south + u(m_random) * m_spanLat;
    const double lon = std::remainder(m_west + u(m_random) * m_spanLon, 360.0);
    return {std::clamp(lat, -89.999, 89.999), lon, 0.0};
}

double GlobeStressFlight::aboveGround(double altitudeM) const {
    return m_groundHeight(m_pose) + altitudeM;
}

void GlobeStressFlight::cruise(double speedMps, double altitudeM) {
    m_cruising = true;
    m_phase = FlightPhase::Cruise;
    m_speedMps = speedMps;
    m_altitudeM = altitudeM;
    // From the south-west tenth of the data toward its north-east.
    m_pose.where = {m_south + 0.1 * m_spanLat, std::remainder(m_west + 0.1 * m_spanLon, 360.0),
                    0.0};
    m_pose.headingDeg = 45.0;
    m_pose.pitchDeg = -10.0;
}

void GlobeStressFlight::teleport() {
    // Mostly over the data, a quarter anywhere on the planet (uniform over the sphere), from
    // two samples above the ground to orbit, looking anywhere between straight down and
    // just below the horizon.
    std::uniform_real_distribution<double> u(0.0, 1.0);
    if (u(m_random) < 0.75) {
        m_pose.where = randomPlaceInData();
    } else {
        m_pose.where = {std::asin(2.0 * u(m_random) - 1.0) / kDegree, 360.0 * u(m_random) - 180.0,
                        0.0};
    }
    m_altitudeM = std::exp(std::lerp(std::log(2.0 * m_spacingM), std::log(kOrbitM), u(m_random)));
    m_pose.headingDeg = 360.0 * u(m_random) - 180.0;
    m_pose.pitchDeg = std::lerp(-90.0, -std::max(5.0, horizonDipDeg(m_altitudeM)), u(m_random));
    m_pose.where.height = aboveGround(m_altitudeM);
    m_nextTeleportS = m_phaseLeftS - std::lerp(0.25, 0.75, u(m_random));
    ++m_teleports;
}

void GlobeStressFlight::startPhase() {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    m_phase = static_cast<FlightPhase>(std::uniform_int_distribution<int>(0, 2)(m_random));
    m_phaseLeftS = 1.0 + 2.0 * u(m_random);
    switch (m_phase) {
        case FlightPhase::Teleport:
            teleport();
            break;
        case FlightPhase::LowFlight:
            // A few samples above the ground at a fifth of the data's extent per second.
            m_pose.where = randomPlaceInData();
            m_altitudeM = std::lerp(1.0, 10.0, u(m_random)) * m_spacingM;
            m_speedMps = std::lerp(0.1, 0.3, u(m_random)) * m_extentM;
            m_pose.headingDeg = 360.0 * u(m_random) - 180.0;
            m_pose.pitchDeg = -std::lerp(3.0, 23.0, u(m_random));
            break;
        case FlightPhase::ZoomBurst:
            // From orbit to two samples above the ground within the phase: exponentially, so
            // the wanted set changes completely at every scale on the way down.
            m_pose.where = randomPlaceInData();
            m_altitudeM = kOrbitM;
            m_diveRatePerS = std::log(kOrbitM / (2.0 * m_spacingM)) / m_phaseLeftS;
            m_pose.headingDeg = 360.0 * u(m_random) - 180.0;
            m_divePitchDeg = -std::lerp(35.0, 90.0, u(m_random));
            break;
        case FlightPhase::Cruise:
            break;  // not a stress phase: cruise() sets it
    }
}

void GlobeStressFlight::step(double dt, runtime::Camera& camera) {
    if (m_cruising) {
        runtime::GlobeController::moveOverGround(m_pose, m_speedMps * dt, 0.0);
        // Turn round at the ends of the data (its south-west and north-east tenths).
        const double northFraction = (m_pose.where.latitudeDeg - m_south) / m_spanLat;
        if ((northFraction > 0.9 && std::abs(m_pose.headingDeg) < 90.0) ||
            (northFraction < 0.1 && std::abs(m_pose.headingDeg) > 90.0))
            m_pose.headingDeg = std::remainder(m_pose.headingDeg + 180.0, 360.0);
    } else {
        m_phaseLeftS -= dt;
        if (m_phaseLeftS <= 0.0) startPhase();
        switch (m_phase) {
            case FlightPhase::Teleport:
                if (m_phaseLeftS <= m_nextTeleportS) teleport();
                m_pose.headingDeg = std::remainder(m_pose.headingDeg + 30.0 * dt, 360.0);
                break;
            case FlightPhase::LowFlight: {
                runtime::GlobeController::moveOverGround(m_pose, m_speedMps * dt, 0.0);
                // Turn back toward the data's centre when leaving it.
                const double northFraction = (m_pose.where.latitudeDeg - m_south) / m_spanLat;
                const double eastFraction =
                    std::remainder(m_pose.where.longitudeDeg - m_west, 360.0) / m_spanLon;
                if (northFraction < 0.0 || northFraction > 1.0 || eastFraction < 0.0 ||
                    eastFraction > 1.0)
                    m_pose.headingDeg = std::remainder(m_pose.headingDeg + 180.0, 360.0);
                break;
            }
            case FlightPhase::ZoomBurst:
                m_altitudeM =
                    std::max(2.0 * m_spacingM, m_altitudeM * std::exp(-m_diveRatePerS * dt));
                // Looking at the planet all the way down.
                m_pose.pitchDeg = std::min(m_divePitchDeg, -horizonDipDeg(m_altitudeM));
                break;
            case FlightPhase::Cruise:
                break;
        }
    }
    m_pose.where.height = aboveGround(m_altitudeM);
    runtime::placeOnGlobe(camera, m_pose);
}

}  // namespace terrain::tools
