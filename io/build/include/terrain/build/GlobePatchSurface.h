// GlobePatchSurface: the surface a globe patch is drawn as, in double: flat triangles between
// its samples, each sample at its height along its ellipsoid normal (terrain::globe). Err(P)
// of a globe pyramid is measured against it: the height, along a source sample's own normal,
// at which that normal pierces the patch's triangles, for both diagonals of the cell (the
// tessellator chooses one). This is the error the reference renderer measures on screen
// (along the normal), so the bound needs no model of curvature or projection: it is exact at
// every source sample.
#pragma once

#include "terrain/globe/GlobePatch.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace terrain::io {

class GlobePatchSurface {
public:
    /// When its samples' positions are computed: all at once (a surface many threads share),
    /// or a row of them the first time a cell beside it is asked for. A surface made for the
    /// samples of a few source rows touches a few of its rows: a coarse patch spans
    /// thousands of source rows, and the whole build measures them in bands of 16.
    enum class Positions { AllNow, RowsOnDemand };

    /// `heights`: the patch's tile, (quads + 3)² samples with the one-sample apron, row-major.
    /// RowsOnDemand: the surface belongs to one thread, and `heights` must outlive it.
    GlobePatchSurface(const globe::GlobePatchId& id, int quads, std::span<const float> heights,
                      Positions positions = Positions::AllNow);

    /// The drawn heights along `unitNormal` (a direction inside the patch or on its border),
    /// with the cell's a–d diagonal and with its b–c diagonal: the ellipsoid height of the
    /// point where the normal line through the surface point of `unitNormal` meets the
    /// triangle of the cell it passes through.
    std::pair<double, double> drawnHeights(const glm::dvec3& unitNormal) const;
    /// The same where the caller has the normal's face point (globe::facePointOf, on this
    /// patch's face): the same heights to the bit, without projecting it again (two
    /// arctangents a source sample on the build's hot path). facePointOf's clamp to the face
    /// changes nothing: the point is clamped onto the patch here.
    std::pair<double, double> drawnHeights(const glm::dvec3& unitNormal,
                                           const globe::FacePoint& at) const;
    /// The same where the caller also has the normal's point on the ellipsoid
    /// (Wgs84::pointAlongNormal(unitNormal, 0), the line's origin), kept for many patches.
    std::pair<double, double> drawnHeights(const glm::dvec3& unitNormal, const globe::FacePoint& at,
                                           const glm::dvec3& origin) const;

    const globe::GlobePatchId& id() const { return m_id; }

private:
    std::pair<double, double> drawnHeights(const glm::dvec3& unitNormal, double s, double t,
                                           const glm::dvec3& origin) const;

    const glm::dvec3& position(int i, int j) const {
        return m_positions[static_cast<std::size_t>(j * (m_quads + 1) + i)];
    }
    // Sample row j's positions, unless made.
    void makeRow(int j) const;

    globe::GlobePatchId m_id;
    int m_quads = 0;
    std::span<const float> m_heights;
    globe::PatchSampleDirections m_directions;
    // (quads + 1)², ECEF, the apron left out; RowsOnDemand: rows made as they are needed.
    mutable std::vector<glm::dvec3> m_positions;
    mutable std::vector<std::uint8_t> m_rowMade;  // RowsOnDemand: per row; else empty
};

}  // namespace terrain::io
