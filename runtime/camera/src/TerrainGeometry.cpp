// TerrainGeometry: pixel spacing from the georeference; patch boxes from the layout.
#include "terrain/runtime/TerrainGeometry.h"

#include <GeographicLib/LocalCartesian.hpp>

#include <cmath>

namespace terrain::runtime {
namespace {

glm::dvec2 spacingFor(const io::Georeference& g, const io::PyramidLayout& layout) {
    switch (g.crsKind) {
        case io::CrsKind::Projected:
            return {g.pixelSizeX, g.pixelSizeY};
        case io::CrsKind::Unknown:
            return {1.0, 1.0};
        case io::CrsKind::Geographic:
            break;
    }
    // Metres of one pixel east and north at the DEM's centre, on the WGS84 ellipsoid.
    const double centreLon =
        g.originX + 0.5 * static_cast<double>(layout.rasterWidth()) * g.pixelSizeX;
    const double centreLat =
        g.originY - 0.5 * static_cast<double>(layout.rasterHeight()) * g.pixelSizeY;
    const GeographicLib::LocalCartesian local(centreLat, centreLon, 0.0);
    double east = 0.0, north = 0.0, up = 0.0;
    local.Forward(centreLat, centreLon + g.pixelSizeX, 0.0, east, north, up);
    const double dx = std::abs(east);
    local.Forward(centreLat + g.pixelSizeY, centreLon, 0.0, east, north, up);
    const double dy = std::abs(north);
    return {dx, dy};
}

// Projected: the centre of pixel (0, 0) in map coordinates (pixel-is-area registration).
glm::dvec2 originFor(const io::Georeference& g) {
    if (g.crsKind != io::CrsKind::Projected) return {0.0, 0.0};
    return {g.originX + 0.5 * g.pixelSizeX, g.originY - 0.5 * g.pixelSizeY};
}

}  // namespace

TerrainGeometry::TerrainGeometry(const io::PyramidManifest& manifest)
    : m_layout(manifest.layout),
      m_spacing(spacingFor(manifest.georeference, manifest.layout)),
      m_origin(originFor(manifest.georeference)),
      m_minHeight(manifest.statistics.minHeight),
      m_maxHeight(manifest.statistics.maxHeight) {}

glm::dvec2 TerrainGeometry::patchNorthWest(const io::PatchId& id) const {
    const double step = static_cast<double>(m_layout.levelStep(id.level));
    return worldOfSample(static_cast<double>(m_layout.patchOriginX(id)) * step,
                         static_cast<double>(m_layout.patchOriginY(id)) * step);
}

glm::dvec2 TerrainGeometry::patchSize(int level) const {
    const double samples =
        static_cast<double>(m_layout.patchQuads()) * static_cast<double>(m_layout.levelStep(level));
    return {samples * m_spacing.x, samples * m_spacing.y};
}

Aabb TerrainGeometry::patchBounds(const io::PatchId& id, const io::PatchInfo& info) const {
    const glm::dvec2 nw = patchNorthWest(id);
    const glm::dvec2 size = patchSize(id.level);
    return Aabb{.min = {nw.x, nw.y - size.y, static_cast<double>(info.minHeight)},
                .max = {nw.x + size.x, nw.y, static_cast<double>(info.maxHeight)}};
}

glm::dvec2 TerrainGeometry::demSize() const {
    return {static_cast<double>(m_layout.rasterWidth() - 1) * m_spacing.x,
            static_cast<double>(m_layout.rasterHeight() - 1) * m_spacing.y};
}

}  // namespace terrain::runtime
