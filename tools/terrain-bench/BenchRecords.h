// BenchRecords: what terrain-bench measures — one FrameRecord per (method, threshold,
// frame), the per-threshold ThresholdSummary derived from them — and the two CSV files that
// hold them (docs/accuracy.md, "terrain-bench"). Column names carry their units and are
// stable: the chart tool (tools/charts/terrain_charts.py) reads them by name.
#pragma once

#include "terrain/base/Result.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <filesystem>
#include <limits>
#include <span>
#include <string>
#include <vector>

namespace terrain::tools {

inline constexpr double kNoValue = std::numeric_limits<double>::quiet_NaN();

struct FrameRecord {
    std::string method;        ///< the LOD method, "yusov2011"
    std::string pose;          ///< --stability: the stress pose (StressPoses.h); else empty
    double thresholdPx = 0.0;  ///< ε of both LOD stages
    std::uint64_t frame = 0;
    double pathTimeS = 0.0;          ///< where on the camera path
    glm::dvec3 cameraPosition{0.0};  ///< world metres, so any frame can be looked at again
    double cameraYawDeg = 0.0;
    double cameraPitchDeg = 0.0;
    /// Above the surface's datum: the DEM's zero on the plane, the ellipsoid on the globe.
    double cameraHeightM = kNoValue;

    // Speed.
    std::uint64_t triangles = 0;  ///< GL_PRIMITIVES_GENERATED of the LOD draw (skirts included)
    std::uint64_t patches = 0;
    /// Patches the LOD culled and nodes in its tree this frame: the "culled" and
    /// "traversed" columns of Livny 2007's Table 1 (LodUpdateStats: for the RTIN, subtrees
    /// culled and bintree nodes visited).
    std::uint64_t patchesCulled = 0;
    std::uint64_t lodNodes = 0;
    /// Patches behind the horizon (the globe's) and nodes the culling walk visited.
    std::uint64_t horizonCulled = 0;
    std::uint64_t lodVisited = 0;
    /// Of the patches drawn, those drawing an ancestor's tile (virtual), none (bare: the
    /// ellipsoid) and a source's own grid (native tiles): on the globe, which surface the
    /// frame's error is of (LodUpdateStats).
    std::uint64_t patchesVirtual = 0;
    std::uint64_t patchesBare = 0;
    std::uint64_t patchesNative = 0;
    /// Of the native draws, windows below a whole tile (NativeWindowTree), and the deepest.
    std::uint64_t nativeWindows = 0;
    int nativeWindowDepthMax = 0;
    std::uint64_t drawCalls = 0;
    double lodUpdateUs = kNoValue;    ///< the frame's first LOD update for this camera
    double gpuMs = kNoValue;          ///< GL_TIME_ELAPSED of the draw (CPU time on llvmpipe)
    double drawMs = kNoValue;         ///< wall time of the draw up to glFinish
    double frameMs = kNoValue;        ///< beginFrame + draw up to glFinish + endFrame, wall
    std::uint64_t residentBytes = 0;  ///< GPU layers used × bytes per layer + CPU cache bytes
    bool waitedForStreaming = false;  ///< splits waited for tiles; the view was settled first
    bool settled = true;              ///< false: streaming did not settle; measured as drawn

    // Accuracy against the reference.
    double errorMaxPx = kNoValue;
    double errorMeanPx = kNoValue;
    double errorP99Px = kNoValue;
    std::uint64_t errorPixels = 0;
    std::uint64_t errorOverThresholdPixels = 0;
    double errorFixedDiagonalMaxPx = kNoValue;
    /// The largest error of any one pixel (errorMaxPx needs two adjacent pixels to agree;
    /// ScreenSpaceError.h).
    double errorMaxSinglePixelPx = kNoValue;
    /// The largest error of any one pixel measured at exactly its drawn x, y, without the
    /// horizontal tolerance (ScreenSpaceError.h): larger only on very steep slopes.
    double errorMaxExactPositionPx = kNoValue;
    /// Against the probe's second truth, where it has one (on the globe the pyramid's own
    /// finest level: the LOD's error alone, without the finest level's resampling of the
    /// sources; AccuracyProbe.h).
    double lodErrorMaxPx = kNoValue;
    /// Where errorMaxPx was found: pixel (x right, y down from the top row) and the drawn
    /// surface point there, world metres.
    int errorWorstX = -1;
    int errorWorstY = -1;
    glm::dvec3 errorWorstWorld{0.0};
    std::uint64_t skirtPixels = 0;
    double skirtErrorMaxPx = kNoValue;
    /// Skirt pixels whose distance to the truth is unbounded (ScreenSpaceError.h).
    std::uint64_t skirtUnboundedPixels = 0;
    /// Surface pixels whose error could not be measured (ScreenSpaceError.h): the frame
    /// counts as over ε, since nothing shows it is within.
    std::uint64_t nonFinitePixels = 0;
    double rmse = kNoValue;
    double psnrDb = kNoValue;
    std::uint64_t crackPixels = 0;
    std::uint64_t uncoveredPixels = 0;
    /// LOD terrain where the reference shows none within ⌈ε⌉ (FrameAccuracy::overdrawnPixels).
    std::uint64_t overdrawnPixels = 0;
    /// Pixels where two patches meet that stand out from both sides and from the reference
    /// (AccuracyProbe, BoundaryArtefacts.h); NaN for a method that draws no patch ids.
    double boundaryArtefactPixels = kNoValue;
    /// Edge pixels standing out at silhouettes, which the detector cannot judge
    /// (BoundaryArtefacts::silhouettePixels); NaN without patch ids.
    double boundarySilhouettePixels = kNoValue;
    /// The steepest slope a source seam in view adds (metres per metre) and that seam's
    /// source's 99th-percentile slope (SeamsInView.h); NaN with no seam in view.
    double seamSlope = kNoValue;
    double seamSourceSlopeP99 = kNoValue;
    /// The shading step the LOD adds across patch boundaries and inside patches, and their
    /// difference, 8-bit luma levels (AccuracyProbe, BoundaryShading.h); NaN without patch
    /// ids.
    double shadingStepBoundaryLevels = kNoValue;
    double shadingStepInteriorLevels = kNoValue;
    double shadingSeamLevels = kNoValue;
    /// Enclosed uncovered pixels where the reference is thinner than a pixel: not cracks.
    std::uint64_t diagonalUncoveredPixels = 0;
    double poppingLevels = kNoValue;
    double lodChangeLevels = kNoValue;
    double referenceChangeLevels = kNoValue;
    /// The image change the LOD's switch alone makes, 8-bit levels: the mean of |L − L'|
    /// (mean R, G, B difference) over the pixels both show terrain, L this frame and L' the
    /// previous frame's LOD drawn from this frame's camera, so the camera's motion is not in
    /// it (popping_levels has it, less the reference's change). yusov2011 only: the other
    /// methods' draws do not take a separate LOD camera (runtime::lodSwitchChange).
    double lodSwitchLevels = kNoValue;
    /// The share of those pixels whose change is a jump (LodSwitchChange::jumpShare).
    double lodSwitchJumpShare = kNoValue;
    std::uint64_t referenceTriangles = 0;
    double referenceMs = kNoValue;
    /// The draped imagery (unlit, no fog) against ImageryReference (every layer read from disk
    /// at the level each pixel needs), over the pixels it wholly covers: PSNR (dB), the
    /// largest channel difference (8-bit levels), pixels over ImageryFrameComparison::
    /// kVisibleLevels, and the bottom layer's texels per pixel (median; share in 0.5–2).
    /// NaN where the pyramid has no imagery or the method drapes none.
    double imageryPsnrDb = kNoValue;
    double imageryMaxLevels = kNoValue;
    double imageryVisiblePixels = kNoValue;
    double imageryComparedPixels = kNoValue;
    /// Terrain pixels the layers leave partly or wholly uncovered (the tint shows).
    double imageryUncoveredPixels = kNoValue;
    double imageryTexelsPerPixel = kNoValue;
    double imageryTexelsInRange = kNoValue;
    /// The texels per pixel the GPU drew (TerrainStyle::imageryTexelsPerPixel, read back from
    /// the same draped frame): the bottom showing layer's, at the tile level the shader
    /// sampled, over every pixel with imagery: 5th, 50th and 95th percentiles and the share in
    /// 0.5–2 (ImageryTexelsPerPixel.h). NaN as above, or where no pixel shows imagery.
    double imageryGpuTexelsPerPixelP5 = kNoValue;
    double imageryGpuTexelsPerPixelP50 = kNoValue;
    double imageryGpuTexelsPerPixelP95 = kNoValue;
    double imageryGpuTexelsInRange = kNoValue;
};

struct ThresholdSummary {
    std::string method;
    double thresholdPx = 0.0;
    std::uint64_t frames = 0;
    double trianglesMean = 0.0;
    std::uint64_t trianglesMax = 0;
    double patchesMean = 0.0;
    std::uint64_t patchesMax = 0;
    std::uint64_t drawCallsMax = 0;
    double lodUpdateUsMean = kNoValue;
    double lodUpdateUsP95 = kNoValue;
    double gpuMsMean = kNoValue;
    double drawMsMean = kNoValue;
    double frameMsMean = kNoValue;
    double frameMsP95 = kNoValue;
    std::uint64_t residentBytesMax = 0;
    double errorMaxPx = kNoValue;        ///< largest over every frame
    double errorMaxMedianPx = kNoValue;  ///< median over frames of each frame's largest
    double errorMeanPx = kNoValue;       ///< mean over frames of each frame's mean
    double errorP99MeanPx = kNoValue;    ///< mean over frames of each frame's p99
    double errorP99MaxPx = kNoValue;     ///< largest over frames of each frame's p99
    /// Frames whose error max > ε + tolerance, or with a pixel that could not be measured.
    std::uint64_t framesOverThreshold = 0;
    std::uint64_t nonFinitePixelsTotal = 0;
    double errorFixedDiagonalMaxPx = kNoValue;
    double errorMaxSinglePixelPx = kNoValue;
    double errorMaxExactPositionPx = kNoValue;
    double lodErrorMaxPx = kNoValue;  ///< FrameRecord::lodErrorMaxPx, largest over every frame
    /// Frames whose lodErrorMaxPx > ε + tolerance (0 without a second truth).
    std::uint64_t lodFramesOverThreshold = 0;
    /// Patches behind the horizon over nodes the culling walk visited, all frames.
    double horizonCulledFraction = kNoValue;
    double rmseMean = kNoValue;
    double psnrDbMean = kNoValue;
    double psnrDbMin = kNoValue;
    /// FrameRecord::imagery*: the mean and worst (lowest) PSNR, and the worst frame.
    double imageryPsnrDbMean = kNoValue;
    double imageryPsnrDbMin = kNoValue;
    double imageryWorstFrame = kNoValue;
    double imageryMaxLevels = kNoValue;
    double imageryVisiblePixelsTotal = kNoValue;
    double imageryUncoveredPixelsTotal = kNoValue;
    double imageryTexelsPerPixelMedian = kNoValue;
    double imageryTexelsInRangeMean = kNoValue;
    /// FrameRecord::imageryGpu*: the median over the frames of each percentile, and the mean
    /// share in range.
    double imageryGpuTexelsPerPixelP5Median = kNoValue;
    double imageryGpuTexelsPerPixelMedian = kNoValue;
    double imageryGpuTexelsPerPixelP95Median = kNoValue;
    double imageryGpuTexelsInRangeMean = kNoValue;
    std::uint64_t crackPixelsTotal = 0;
    std::uint64_t overdrawnPixelsTotal = 0;  ///< FrameRecord::overdrawnPixels over every frame
    /// FrameRecord::boundaryArtefactPixels over every frame; NaN where never measured.
    double boundaryArtefactPixelsTotal = kNoValue;
    /// FrameRecord::boundarySilhouettePixels over every frame; NaN where never measured.
    double boundarySilhouettePixelsTotal = kNoValue;
    /// FrameRecord::seamSlope: the largest over the frames (NaN where no seam was in view),
    /// and the frames where it exceeded its source's 99th-percentile slope.
    double seamSlopeMax = kNoValue;
    std::uint64_t framesSeamOverSourceSlope = 0;
    /// FrameRecord::shadingSeamLevels: the largest and the mean over the frames.
    double shadingSeamLevelsMax = kNoValue;
    double shadingSeamLevelsMean = kNoValue;
    double poppingLevelsMean = kNoValue;
    double lodSwitchLevelsMean = kNoValue;
    double lodSwitchJumpShareMean = kNoValue;
    std::uint64_t framesWaited = 0;
    std::uint64_t framesUnsettled = 0;  ///< measured although streaming had not settled
};

/// Per (method, threshold) in the order they first appear in `records`.
std::vector<ThresholdSummary> summarise(std::span<const FrameRecord> records, double tolerancePx);

/// frames.csv: one row per record. summary.csv: one row per summary; `gpuMsSource`
/// ("gl-timer-query" or "llvmpipe-cpu") is written in a column of every row of both.
/// `withPose` adds the pose column after the threshold (stability.csv).
Status writeFramesCsv(const std::filesystem::path& path, std::span<const FrameRecord> records,
                      const std::string& gpuMsSource, bool withPose = false);
Status writeSummaryCsv(const std::filesystem::path& path,
                       std::span<const ThresholdSummary> summaries, const std::string& gpuMsSource);

}  // namespace terrain::tools
