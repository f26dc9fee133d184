// TerrainGeometry: where a pyramid's samples and patches lie in the world frame the
// runtime works in: x east, y north, z up, metres, double precision (DESIGN.md,
// "Coordinates and precision"). Sample (0, 0) of the DEM is the world origin.
//
// Projected pyramids use their pixel size; unknown CRSs use 1 m; geographic pyramids use
// the local east/north metres of one pixel at the DEM's centre on the WGS84 ellipsoid
// (GeographicLib::LocalCartesian), a planar approximation that is exact at the centre.
// The ellipsoidal mapping will replace spacingFor() and patchBounds() only: callers work
// with world boxes and never with sample spacings directly.
#pragma once

#include "terrain/io/PatchRecord.h"
#include "terrain/io/PyramidLayout.h"
#include "terrain/io/PyramidManifest.h"
#include "terrain/runtime/Aabb.h"

#include <glm/vec2.hpp>

namespace terrain::runtime {

class TerrainGeometry {
public:
    explicit TerrainGeometry(const io::PyramidManifest& manifest);

    const io::PyramidLayout& layout() const { return m_layout; }
    /// Metres between two DEM samples, east (x) and south (y).
    glm::dvec2 sampleSpacing() const { return m_spacing; }

    /// World x, y of a finest-level (DEM) sample position; fractional samples allowed.
    glm::dvec2 worldOfSample(double column, double row) const {
        return {column * m_spacing.x, -row * m_spacing.y};
    }
    /// The DEM sample position (fractional) of a world x, y.
    glm::dvec2 sampleOfWorld(double x, double y) const {
        return {x / m_spacing.x, -y / m_spacing.y};
    }

    /// The patch's footprint (its N × N samples without apron) and the heights of `info`.
    Aabb patchBounds(const io::PatchId& id, const io::PatchInfo& info) const;
    /// Footprint only: world x, y of the patch's north-west corner and its size in metres.
    glm::dvec2 patchNorthWest(const io::PatchId& id) const;
    glm::dvec2 patchSize(int level) const;

    /// The DEM's extent in world x, y: [0, width − 1] × [−(height − 1), 0] samples.
    glm::dvec2 demSize() const;

    /// The manifest's height range, metres.
    double minHeight() const { return m_minHeight; }
    double maxHeight() const { return m_maxHeight; }

private:
    io::PyramidLayout m_layout;
    glm::dvec2 m_spacing{1.0};
    double m_minHeight = 0.0;
    double m_maxHeight = 0.0;
};

}  // namespace terrain::runtime
