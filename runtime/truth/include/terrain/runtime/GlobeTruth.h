// GlobeTruth: the globe's ground truth (TruthSurface.h; docs/globe.md): the vertical through
// a drawn point is the ellipsoid's normal there, W_lod's geodetic latitude, longitude and
// height follow exactly (GeographicLib), and a reference surface gives its heights on that
// normal. The reference is a function, so that runtime/truth needs no builder: the sources'
// full-resolution surface (io::GlobeSourceSurface) for the error the frame shows, or the
// pyramid's own finest level (io::GlobeGroundQuery) for the LOD's error alone, what it chose
// against what the pyramid holds, without the finest level's resampling of the sources (its
// Err(P), which no LOD can go below and which shows once the camera is close to the ground).
#pragma once

#include "terrain/runtime/TruthSurface.h"

#include <functional>
#include <utility>

namespace terrain::runtime {

/// A reference surface's heights at a latitude and longitude (degrees) on the two
/// triangulations of its cell there, metres along the ellipsoid normal; an error where it
/// cannot be read (it fails the measure).
using GlobeReferenceHeights = std::function<Result<std::pair<double, double>>(double, double)>;

/// One thread. The globe has no edge: every drawn point has truth below or above it. It is
/// measured at exactly its own position (no horizontal tolerance), and every enclosed clear
/// pixel counts as a crack.
class GlobeTruth final : public TruthSurface {
public:
    explicit GlobeTruth(GlobeReferenceHeights heights) : m_heights(std::move(heights)) {}

    Result<TruthVertical> verticalAt(const glm::dvec3& world, const glm::dvec3& relative,
                                     const FrameProjection& frame) override;
    glm::dvec3 relativePointAt(const TruthVertical& vertical, const glm::dvec3& relative,
                               const FrameProjection& frame, double heightM) const override;
    double horizontalTolerancePx() const override { return 0.0; }
    /// Never called (no horizontal tolerance): the vertical as it is.
    Result<TruthVertical> widened(const TruthVertical& vertical, const glm::dvec3&,
                                  double) override {
        return vertical;
    }
    Result<bool> everyTriangulationCovers(const glm::dvec3&, const glm::dvec3&, double) override {
        return true;
    }

private:
    GlobeReferenceHeights m_heights;
};

}  // namespace terrain::runtime
