// TruthSurface: the ground truth the measured screen-space error (ScreenSpaceError.h) and
// the accuracy probe's crack count hold a frame against, whatever surface it was drawn on:
// the plane's full-resolution DEM (PlaneTruth.h) or the globe's sources or finest level
// (GlobeTruth.h). The measure unprojects each drawn pixel to W_lod; the truth says where
// its surface lies on the vertical through W_lod (the plane's z axis, the ellipsoid's
// normal on the globe) and where a height on that vertical is, camera-relative, so that
// one loop projects both and measures them in pixels.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/runtime/ScreenProjection.h"

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace terrain::runtime {

/// How a frame was drawn: the camera's position (world metres) and its camera-relative
/// projection to pixels (rows bottom-up).
struct FrameProjection {
    glm::dvec3 cameraPosition{0.0};
    glm::dmat4 viewProjection{1.0};
    int widthPx = 0;
    int heightPx = 0;

    /// The pixel a camera-relative point projects to; NaN behind the camera.
    glm::dvec2 toPixels(const glm::dvec3& relative) const {
        return projectToPixels(viewProjection, widthPx, heightPx, relative);
    }
};

/// The truth on the vertical through a drawn point W_lod.
struct TruthVertical {
    bool inside = false;  ///< the truth has a surface there (the plane's DEM ends)
    double drawnM = 0.0;  ///< W_lod's own height along the vertical
    /// The lower and higher of the heights of the truth's two triangulations there (either
    /// diagonal of a cell; docs/accuracy.md): the measure takes the nearer, 0 between them.
    double lowM = 0.0;
    double highM = 0.0;
    double referenceM = 0.0;       ///< the reference renderer's own diagonal's height
    glm::dvec3 up{0.0, 0.0, 1.0};  ///< the vertical's direction (the globe's normal)
};

/// One thread (the render thread in the tools).
class TruthSurface {
public:
    virtual ~TruthSurface() = default;

    /// The truth on the vertical through the drawn point `world` (camera-relative
    /// `relative`) of a frame drawn with `frame`. Errors: truth that cannot be read (a
    /// shard file, a source).
    virtual Result<TruthVertical> verticalAt(const glm::dvec3& world, const glm::dvec3& relative,
                                             const FrameProjection& frame) = 0;

    /// The camera-relative point at `heightM` on `vertical`, whose drawn point is `relative`
    /// from `frame`'s camera.
    virtual glm::dvec3 relativePointAt(const TruthVertical& vertical, const glm::dvec3& relative,
                                       const FrameProjection& frame, double heightM) const = 0;

    /// How far sideways, in pixels at the drawn point's distance, a drawn point may lie from
    /// the exact triangle it belongs to (docs/accuracy.md, "Rasterisation tolerance"); 0:
    /// the point is measured at exactly its own position.
    virtual double horizontalTolerancePx() const = 0;

    /// `vertical` of the drawn point `world` with its low and high heights widened to the
    /// truth's lowest and highest within `radiusM` sideways. Called only when
    /// horizontalTolerancePx() > 0.
    virtual Result<TruthVertical> widened(const TruthVertical& vertical, const glm::dvec3& world,
                                          double radiusM) = 0;

    /// Whether the truth covers the ray from `cameraPosition` along `along` whichever
    /// diagonal splits each of its cells, even lowered by `lowerPerMetre` per metre of
    /// distance from the camera (a surface that far below the truth is still within the
    /// LOD's error bound: ε pixels' angle per metre): a clear LOD pixel there is a crack,
    /// else only evidence of the choice of diagonals or of the LOD's allowed error, such as
    /// a sky sliver's tip between needles reaching a pixel further (AccuracyProbe's
    /// crackPixels()).
    virtual Result<bool> everyTriangulationCovers(const glm::dvec3& cameraPosition,
                                                  const glm::dvec3& along,
                                                  double lowerPerMetre) = 0;
};

}  // namespace terrain::runtime
