// TerrainGeometry: where a pyramid's samples and patches lie in the world frame the
// runtime works in: x east, y north, z up, metres, double precision (DESIGN.md,
// "Coordinates and precision").
//
// Projected pyramids live in their CRS's own coordinates: world x, y of a sample are its
// easting and northing (sample centres, so sample (0, 0) is half a pixel inside the
// georeferenced corner), and a camera path or a jump-to-coordinates speaks the map's
// language. A DEM 10,000 km from the CRS origin costs the GPU nothing: everything reaching
// it is relative to the camera's sample. Unknown CRSs put sample (0, 0) at the origin with
// 1 m spacing; geographic pyramids put it at the origin too, with the local east/north
// metres of one pixel at the DEM's centre on the WGS84 ellipsoid
// (GeographicLib::LocalCartesian), a planar approximation that is exact at the centre.
// The ellipsoidal mapping will replace spacingFor() and patchBounds() only: callers work
// with world boxes and never with sample spacings directly.
#pragma once

#include "terrain/pyramid/PatchRecord.h"
#include "terrain/pyramid/PyramidLayout.h"
#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/runtime/Aabb.h"

#include <glm/vec2.hpp>

namespace terrain::runtime {

class TerrainGeometry {
public:
    explicit TerrainGeometry(const io::PyramidManifest& manifest);

    const io::PyramidLayout& layout() const { return m_layout; }
    /// Metres between two DEM samples, east (x) and south (y).
    glm::dvec2 sampleSpacing() const { return m_spacing; }

    /// World x, y of DEM sample (0, 0), the north-west corner of the DEM's extent.
    glm::dvec2 origin() const { return m_origin; }
    /// World x, y of a finest-level (DEM) sample position; fractional samples allowed.
    glm::dvec2 worldOfSample(double column, double row) const {
        return {m_origin.x + column * m_spacing.x, m_origin.y - row * m_spacing.y};
    }
    /// The DEM sample position (fractional) of a world x, y.
    glm::dvec2 sampleOfWorld(double x, double y) const {
        return {(x - m_origin.x) / m_spacing.x, (m_origin.y - y) / m_spacing.y};
    }
    /// World x, y at fractions of the DEM's extent: (0, 0) is sample (0, 0), the
    /// north-west corner, (1, 1) the south-east corner; fractions outside [0, 1] allowed.
    glm::dvec2 worldAtFraction(double eastFraction, double southFraction) const {
        const glm::dvec2 size = demSize();
        return {m_origin.x + eastFraction * size.x, m_origin.y - southFraction * size.y};
    }

    /// The patch's footprint (its N × N samples without apron) and the heights of `info`.
    Aabb patchBounds(const io::PatchId& id, const io::PatchInfo& info) const;
    /// Footprint only: world x, y of the patch's north-west corner and its size in metres.
    glm::dvec2 patchNorthWest(const io::PatchId& id) const;
    glm::dvec2 patchSize(int level) const;

    /// The size of the DEM's extent in world x, y: (width − 1, height − 1) samples in
    /// metres; it spans worldAtFraction(0, 0) to worldAtFraction(1, 1).
    glm::dvec2 demSize() const;

    /// The manifest's height range, metres.
    double minHeight() const { return m_minHeight; }
    double maxHeight() const { return m_maxHeight; }

private:
    io::PyramidLayout m_layout;
    glm::dvec2 m_spacing{1.0};
    glm::dvec2 m_origin{0.0};
    double m_minHeight = 0.0;
    double m_maxHeight = 0.0;
};

}  // namespace terrain::runtime
