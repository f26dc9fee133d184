// PlaneTruth: the plane's ground truth (TruthSurface.h), the full-resolution DEM
// (FullResolutionSurface): the vertical is the world's z axis, the truth ends at the DEM's
// extent, and a drawn point is measured against the DEM's lowest and highest heights within
// a fraction of a pixel sideways (docs/accuracy.md, "Rasterisation tolerance").
#pragma once

#include "terrain/runtime/FullResolutionSurface.h"
#include "terrain/runtime/TruthSurface.h"

namespace terrain::runtime {

/// How far sideways (in pixels, at the drawn point's distance) a drawn point may lie from
/// the exact triangle it belongs to: the same 0.05 px the vertical measure allows
/// (docs/accuracy.md, "Rasterisation tolerance").
inline constexpr double kHorizontalTolerancePx = 0.05;

/// One thread; refers to `surface`, which must outlive it.
class PlaneTruth final : public TruthSurface {
public:
    /// The truth of `surface`, each drawn point measured against its heights within
    /// `horizontalTolerancePx` of its x, y (0: at exactly its x, y).
    explicit PlaneTruth(FullResolutionSurface& surface,
                        double horizontalTolerancePx = kHorizontalTolerancePx)
        : m_surface(surface), m_horizontalTolerancePx(horizontalTolerancePx) {}

    FullResolutionSurface& surface() { return m_surface; }

    /// A pixel centre just past the DEM's edge (less than a pixel on screen) is measured at
    /// the edge: the rasteriser snaps vertices to sub-pixel positions, so it may be covered.
    Result<TruthVertical> verticalAt(const glm::dvec3& world, const glm::dvec3& relative,
                                     const FrameProjection& frame) override;
    glm::dvec3 relativePointAt(const TruthVertical& vertical, const glm::dvec3& relative,
                               const FrameProjection& frame, double heightM) const override;
    double horizontalTolerancePx() const override { return m_horizontalTolerancePx; }
    Result<TruthVertical> widened(const TruthVertical& vertical, const glm::dvec3& world,
                                  double radiusM) override;
    Result<bool> everyTriangulationCovers(const glm::dvec3& cameraPosition, const glm::dvec3& along,
                                          double lowerPerMetre) override;

private:
    FullResolutionSurface& m_surface;
    double m_horizontalTolerancePx = kHorizontalTolerancePx;
};

}  // namespace terrain::runtime
