#include "terrain/build/GlobePatchSurface.h"

#include "terrain/base/Assert.h"
#include "terrain/globe/Wgs84.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace terrain::io {

namespace {

struct Hit {
    double height = 0.0;
    double inside = -1e300;  // the smallest barycentric coordinate: ≥ 0 inside the triangle
};

// Where the line origin + τ·direction meets the plane of (a, b, c): τ is the height, since
// the origin is the ellipsoid point of the normal `direction`. Inlined into drawnHeights, so
// that its four calls share the edges and the origin's offsets they have in common (the same
// operations on the same values: the same bits), a globe build's hottest loop.
[[gnu::always_inline]] inline Hit pierce(const glm::dvec3& origin, const glm::dvec3& direction,
                                         const glm::dvec3& a, const glm::dvec3& b,
                                         const glm::dvec3& c) {
    const glm::dvec3 normal = glm::cross(b - a, c - a);
    const double denominator = glm::dot(direction, normal);
    if (denominator == 0.0) return {};
    const double tau = glm::dot(a - origin, normal) / denominator;
    const glm::dvec3 p = origin + tau * direction;
    const double area = glm::dot(normal, normal);
    const double wa = glm::dot(glm::cross(b - p, c - p), normal) / area;
    const double wb = glm::dot(glm::cross(c - p, a - p), normal) / area;
    const double wc = 1.0 - wa - wb;
    return {tau, std::min({wa, wb, wc})};
}

double better(const Hit& first, const Hit& second) {
    return first.inside >= second.inside ? first.height : second.height;
}

}  // namespace

GlobePatchSurface::GlobePatchSurface(const globe::GlobePatchId& id, int quads,
                                     std::span<const float> heights, Positions positions)
    : m_id(id), m_quads(quads), m_heights(heights), m_directions(id, quads, 0, quads) {
    m_positions.resize(static_cast<std::size_t>((quads + 1) * (quads + 1)));
    if (positions == Positions::RowsOnDemand) {
        m_rowMade.assign(static_cast<std::size_t>(quads + 1), 0);
        return;
    }
    for (int j = 0; j <= quads; ++j) makeRow(j);
    m_heights = {};  // not kept: the caller's tile may go
}

void GlobePatchSurface::makeRow(int j) const {
    const int tile = m_quads + 3;
    for (int i = 0; i <= m_quads; ++i) {
        const double h = m_heights[static_cast<std::size_t>((j + 1) * tile + i + 1)];
        m_positions[static_cast<std::size_t>(j * (m_quads + 1) + i)] =
            globe::Wgs84::pointAlongNormal(m_directions(i, j), h);
    }
}

std::pair<double, double> GlobePatchSurface::drawnHeights(const glm::dvec3& unitNormal) const {
    // The direction's projection on this patch's face (a normal on a cube edge belongs to
    // both faces; clamping below puts a rounding step outside back on the border, where
    // both faces hold the same samples).
    const globe::FaceFrame& frame = globe::faceFrame(m_id.face);
    const double along = glm::dot(unitNormal, glm::dvec3(frame.normal));
    const double s = globe::faceCoordinate(glm::dot(unitNormal, glm::dvec3(frame.right)) / along);
    const double t = globe::faceCoordinate(glm::dot(unitNormal, glm::dvec3(frame.down)) / along);
    return drawnHeights(unitNormal, s, t, globe::Wgs84::pointAlongNormal(unitNormal, 0.0));
}

std::pair<double, double> GlobePatchSurface::drawnHeights(const glm::dvec3& unitNormal,
                                                          const globe::FacePoint& at) const {
    TERRAIN_ASSERT(at.face == m_id.face);
    return drawnHeights(unitNormal, at.s, at.t, globe::Wgs84::pointAlongNormal(unitNormal, 0.0));
}

std::pair<double, double> GlobePatchSurface::drawnHeights(const glm::dvec3& unitNormal,
                                                          const globe::FacePoint& at,
                                                          const glm::dvec3& origin) const {
    TERRAIN_ASSERT(at.face == m_id.face);
    return drawnHeights(unitNormal, at.s, at.t, origin);
}

std::pair<double, double> GlobePatchSurface::drawnHeights(const glm::dvec3& unitNormal, double s,
                                                          double t,
                                                          const glm::dvec3& origin) const {
    // Continuous sample coordinates in the patch, clamped onto it.
    const double n = static_cast<double>(globe::patchesPerFaceSide(m_id.level));
    double gx = (s * n - static_cast<double>(m_id.x)) * m_quads;
    double gy = (t * n - static_cast<double>(m_id.y)) * m_quads;
    gx = std::clamp(gx, 0.0, double(m_quads));
    gy = std::clamp(gy, 0.0, double(m_quads));
    const int ci = std::min(static_cast<int>(gx), m_quads - 1);
    const int cj = std::min(static_cast<int>(gy), m_quads - 1);
    if (!m_rowMade.empty()) {
        for (const int j : {cj, cj + 1}) {
            std::uint8_t& made = m_rowMade[static_cast<std::size_t>(j)];
            if (made == 0) makeRow(j);
            made = 1;
        }
    }
    const glm::dvec3& a = position(ci, cj);
    const glm::dvec3& b = position(ci + 1, cj);
    const glm::dvec3& c = position(ci, cj + 1);
    const glm::dvec3& d = position(ci + 1, cj + 1);
    const double alongAD =
        better(pierce(origin, unitNormal, a, b, d), pierce(origin, unitNormal, a, d, c));
    const double alongBC =
        better(pierce(origin, unitNormal, a, b, c), pierce(origin, unitNormal, b, d, c));
    return {alongAD, alongBC};
}

}  // namespace terrain::io
