// StressFlight: phases of 1–4 s; speeds and altitudes scale with the DEM's extent so a
// small test pyramid and a planet see the same kind of motion.
#include "StressFlight.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace terrain::tools {

std::string_view flightPhaseName(FlightPhase phase) {
    switch (phase) {
        case FlightPhase::Teleport:
            return "teleport";
        case FlightPhase::LowFlight:
            return "low-flight";
        case FlightPhase::ZoomBurst:
            return "zoom-burst";
        case FlightPhase::Cruise:
            return "cruise";
    }
    return "unknown";
}

StressFlight::StressFlight(const runtime::TerrainGeometry& geometry, std::uint64_t seed,
                           std::function<double(double, double)> groundHeight)
    : m_geometry(geometry), m_random(seed), m_groundHeight(std::move(groundHeight)) {}

glm::dvec2 StressFlight::randomPoint() {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const double fx = u(m_random), fy = u(m_random);
    return m_geometry.worldAtFraction(fx, fy);
}

void StressFlight::cruise(double speedMps, double altitudeM) {
    m_cruising = true;
    m_phase = FlightPhase::Cruise;
    m_speedMps = speedMps;
    m_altitudeM = altitudeM;
    m_cruiseStarted = false;  // the first step places the camera
}

void StressFlight::teleport(runtime::Camera& camera) {
    // Anywhere, from a couple of samples above the ground to the whole DEM in view,
    // looking at another random point of the DEM.
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const glm::dvec2 size = m_geometry.demSize();
    const double extent = std::max(size.x, size.y);
    const double spacing = std::min(m_geometry.sampleSpacing().x, m_geometry.sampleSpacing().y);
    const glm::dvec2 p = randomPoint();
    const glm::dvec2 target = randomPoint();
    const double altitude =
        std::exp(std::lerp(std::log(2.0 * spacing), std::log(extent), u(m_random)));
    camera.position = {p.x, p.y, m_groundHeight(p.x, p.y) + altitude};
    camera.lookAt({target.x, target.y, m_groundHeight(target.x, target.y)});
    m_nextTeleportS = m_phaseLeftS - std::lerp(0.25, 0.75, u(m_random));
    ++m_teleports;
}

void StressFlight::startPhase(runtime::Camera& camera) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const glm::dvec2 size = m_geometry.demSize();
    const double extent = std::max(size.x, size.y);
    const double spacing = std::min(m_geometry.sampleSpacing().x, m_geometry.sampleSpacing().y);
    m_phase = static_cast<FlightPhase>(std::uniform_int_distribution<int>(0, 2)(m_random));
    m_phaseLeftS = 1.0 + 2.0 * u(m_random);
    m_baseFovY = camera.fovY;
    const glm::dvec2 start = randomPoint();
    const glm::dvec2 towards = randomPoint();
    m_heading = std::atan2(towards.x - start.x, towards.y - start.y);
    switch (m_phase) {
        case FlightPhase::Teleport:
            teleport(camera);
            break;
        case FlightPhase::LowFlight:
            // A few sample spacings above the ground at a fifth of the DEM per second.
            m_altitudeM = std::lerp(1.0, 10.0, u(m_random)) * spacing;
            m_speedMps = std::lerp(0.1, 0.3, u(m_random)) * extent;
            camera.position = {start.x, start.y, m_groundHeight(start.x, start.y) + m_altitudeM};
            camera.yaw = m_heading;
            camera.pitch = -std::lerp(0.05, 0.4, u(m_random));
            break;
        case FlightPhase::ZoomBurst:
            // Down from the height of the DEM's extent at 3× the extent per second, narrowing
            // the field of view: the wanted set changes completely within frames.
            m_altitudeM = extent;
            m_climbMps = -3.0 * extent;
            camera.position = {start.x, start.y, m_groundHeight(start.x, start.y) + m_altitudeM};
            camera.yaw = m_heading;
            camera.pitch = -std::lerp(0.6, 1.5, u(m_random));
            break;
        case FlightPhase::Cruise:
            break;  // not a stress phase: cruise() sets it
    }
}

void StressFlight::step(double dt, runtime::Camera& camera) {
    if (m_cruising) {
        const glm::dvec2 size = m_geometry.demSize();
        if (!m_cruiseStarted) {  // a tenth of the way along the diagonal
            camera.position = {m_geometry.worldAtFraction(0.1, 0.1), 0.0};
            m_heading = std::atan2(size.x, -size.y);
            m_cruiseStarted = true;
        }
        glm::dvec3& p = camera.position;
        p.x += std::sin(m_heading) * m_speedMps * dt;
        p.y += std::cos(m_heading) * m_speedMps * dt;
        const glm::dvec2 local = glm::dvec2(p) - m_geometry.origin();  // y ≤ 0 over the DEM
        const bool outside = local.x < 0.05 * size.x || local.x > 0.95 * size.x ||
                             local.y > -0.05 * size.y || local.y < -0.95 * size.y;
        if (outside) m_heading += std::numbers::pi;  // turn round at the ends
        p.z = m_groundHeight(p.x, p.y) + m_altitudeM;
        camera.yaw = m_heading;
        camera.pitch = -10.0 * std::numbers::pi / 180.0;
        return;
    }
    m_phaseLeftS -= dt;
    if (m_phaseLeftS <= 0.0) {
        if (m_phase == FlightPhase::ZoomBurst) camera.fovY = m_baseFovY;
        startPhase(camera);
    }
    const glm::dvec2 size = m_geometry.demSize();
    const double spacing = std::min(m_geometry.sampleSpacing().x, m_geometry.sampleSpacing().y);
    switch (m_phase) {
        case FlightPhase::Teleport:
            if (m_phaseLeftS <= m_nextTeleportS) teleport(camera);
            camera.yaw += 0.5 * dt;  // look around between jumps
            break;
        case FlightPhase::LowFlight: {
            glm::dvec3& p = camera.position;
            p.x += std::sin(m_heading) * m_speedMps * dt;
            p.y += std::cos(m_heading) * m_speedMps * dt;
            // Turn back at the DEM's edges.
            const glm::dvec2 o = m_geometry.origin();
            if (p.x < o.x || p.x > o.x + size.x) m_heading = -m_heading;
            if (p.y > o.y || p.y < o.y - size.y) m_heading = std::numbers::pi - m_heading;
            p.x = std::clamp(p.x, o.x, o.x + size.x);
            p.y = std::clamp(p.y, o.y - size.y, o.y);
            p.z = m_groundHeight(p.x, p.y) + m_altitudeM;
            camera.yaw = m_heading;
            break;
        }
        case FlightPhase::ZoomBurst: {
            m_altitudeM = std::max(2.0 * spacing, m_altitudeM + m_climbMps * dt);
            camera.position.z = m_groundHeight(camera.position.x, camera.position.y) + m_altitudeM;
            camera.fovY = std::max(0.2, camera.fovY * std::exp(-0.5 * dt));
            break;
        }
        case FlightPhase::Cruise:
            break;
    }
}

}  // namespace terrain::tools
