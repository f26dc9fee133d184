// AccuracyProbe: one frame's accuracy against ground truth, end to end, for the benchmark
// and the stability tests (docs/accuracy.md), on either surface: it draws a TerrainSession's
// frame into its own framebuffer (with skirts as the style says, and once more without, to
// tell skirt pixels apart), draws the reference (ReferenceRenderer of a ReferenceScene) for
// the same camera, reads both back and computes the measured screen-space error against its
// truths (ScreenSpaceError.h, TruthSurface.h), RMSE/PSNR, crack pixels and popping
// (ImageComparison.h).
#pragma once

#include "terrain/base/Result.h"
#include "terrain/gl/Framebuffer.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/BoundaryShading.h"
#include "terrain/runtime/FrameImages.h"
#include "terrain/runtime/FullResolutionSurface.h"
#include "terrain/runtime/ImageComparison.h"
#include "terrain/runtime/LodStrategy.h"
#include "terrain/runtime/ReferenceRenderer.h"
#include "terrain/runtime/ScreenSpaceError.h"
#include "terrain/runtime/TerrainRenderer.h"
#include "terrain/runtime/TerrainSession.h"
#include "terrain/runtime/TruthSurface.h"

#include <array>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

namespace terrain::runtime {

struct AccuracyProbeOptions {
    int widthPx = 256;
    int heightPx = 192;
    /// Cleared before both draws: pure magenta, which the terrain's shading never
    /// produces, so an LOD pixel of this colour is a crack or a hole.
    std::array<float, 4> clearColor{1.0f, 0.0f, 1.0f, 1.0f};
    std::size_t surfaceBudgetBytes = FullResolutionSurface::kDefaultBudgetBytes;
};

struct LodCapture {
    FrameImages images;  ///< as drawn, with the style's skirts
    /// The same frame drawn without skirts (empty when the style or the method has none).
    std::vector<float> depthWithoutSkirts;
    /// Where its patches lie on screen: patchIdsOf the same frame's patch-id view (empty when
    /// the method draws none, LodMethodInfo::patchIds, or the style is a debug view).
    std::vector<std::uint32_t> patchIds;
    TerrainDrawStats draw;  ///< of the first draw (triangles, GPU ms when style.measure)
    double drawMs = 0.0;    ///< wall time of the first draw up to glFinish
};

struct ReferenceCapture {
    FrameImages images;
    ReferenceDrawStats draw;
    double drawMs = 0.0;  ///< wall time of the reference draw up to glFinish
};

struct FrameAccuracy {
    static constexpr double kNoValue = std::numeric_limits<double>::quiet_NaN();

    ScreenSpaceErrorStats error;  ///< against the probe's first truth
    /// Against its second truth, when it has one: on the globe the pyramid's own finest level,
    /// the LOD's error alone (GlobeTruth.h).
    std::optional<ScreenSpaceErrorStats> lodError;
    /// False when the reference image was partial (ReferenceDrawStats::complete): the image
    /// figures below are then not computed (0, NaN popping) and the error is measured over
    /// every drawn pixel.
    bool comparedWithReference = true;
    ImageDifference image;
    /// Clear colour in the LOD where the reference drew terrain, enclosed by terrain
    /// (countUncoveredPixels), and covered by the full-resolution surface whichever
    /// diagonal splits each cell (everyTriangulationCovers): cracks and holes. Their pixel
    /// indices (the images' row order), ascending: where to look.
    std::vector<std::size_t> cracks;
    std::uint64_t crackPixels() const { return cracks.size(); }
    /// The other enclosed clear pixels: some choice of diagonals leaves them clear too, so
    /// they are no evidence of a hole (cells so steep that the diagonals are pixels apart).
    std::uint64_t diagonalUncoveredPixels = 0;
    /// Pixels where two patches meet that stand out from both sides and from the reference
    /// (findBoundaryArtefacts, BoundaryArtefacts.h); nullopt when the capture has no patch ids.
    std::optional<std::uint64_t> boundaryArtefactPixels;
    /// Those pixels' indices (the images' row order), ascending: where to look.
    std::vector<std::size_t> boundaryArtefacts;
    /// Edge pixels standing out as artefacts would, at silhouettes, where the comparison
    /// with the reference cannot judge them (BoundaryArtefacts::silhouettePixels).
    std::optional<std::uint64_t> boundarySilhouettePixels;
    /// The shading steps across patch boundaries and inside patches against the reference's
    /// (measureBoundaryShading, BoundaryShading.h); nullopt without patch ids.
    std::optional<BoundaryShading> boundaryShading;
    /// All clear-colour LOD pixels where the reference drew terrain, silhouettes included.
    std::uint64_t uncoveredPixels = 0;
    /// LOD terrain pixels with no reference terrain within ⌈ε⌉ (countOverdrawnPixels).
    std::uint64_t overdrawnPixels = 0;
    std::uint64_t referencePixels = 0;  ///< pixels where the reference drew terrain
    std::uint64_t lodPixels = 0;        ///< pixels where the LOD drew anything
    /// ImageComparison's poppingLevels and its two terms; NaN without a previous frame.
    double poppingLevels = kNoValue;
    double lodChangeLevels = kNoValue;
    double referenceChangeLevels = kNoValue;

    /// No NaN among the figures (popping aside when there was no previous frame, the image's
    /// when it was not compared) and no pixel whose measure was not finite.
    bool finite() const;
};

/// The reference's look from the LOD style's (sky colour, fog).
ReferenceStyle referenceStyleOf(const TerrainStyle& style);

/// Render thread only; destroy it before its GL context.
class AccuracyProbe {
public:
    /// A probe drawing `scene` as the reference and measuring against `truths` (one or
    /// two): the first gives the error and confirms the cracks, the second, if any,
    /// FrameAccuracy::lodError. What the scene and the truths read (a pyramid, sources) must
    /// outlive the probe. Errors: the reference's program, the framebuffers.
    static Result<std::unique_ptr<AccuracyProbe>> create(
        std::unique_ptr<ReferenceScene> scene, std::vector<std::unique_ptr<TruthSurface>> truths,
        const AccuracyProbeOptions& options = {});

    /// The plane's probe: opens the pyramid's finest level (FullResolutionSurface) as the
    /// reference scene and the truth (PlaneTruth). `referencePyramid`, when given, is the
    /// pyramid whose finest level is the ground truth instead: the lossless build of a lossy
    /// pyramid (terrain-build --max-error-m), whose own finest level is up to δ off the
    /// source. It must have `pyramid`'s layout and georeference.
    static Result<std::unique_ptr<AccuracyProbe>> create(
        const std::filesystem::path& pyramid, const AccuracyProbeOptions& options = {},
        const std::filesystem::path& referencePyramid = {});

    /// Draws and reads back the ground truth for `camera` (viewport = the options' size).
    Result<ReferenceCapture> renderReference(const Camera& camera, const ReferenceStyle& style);

    /// Draws the strategy's frame for `camera` (between its beginFrame and endFrame) with
    /// `style`, then (for a method with skirts) without them, then (for a method that draws
    /// them, a shaded style) its patch ids, and reads them back. Any LOD method (LodStrategy.h).
    LodCapture captureLod(LodStrategy& session, const Camera& camera, const TerrainStyle& style);

    /// One draw of the session's frame in `style`, read back (no second draw without skirts,
    /// no patch ids): the draped imagery's frame (ImageryReference.h). With
    /// `imageryTexelsPerPixel` the draw is the renderer's texels-per-pixel variant
    /// (TerrainStyle::imageryTexelsPerPixel; the session's renderer must have been built with
    /// TerrainRendererOptions::imageryTexelsPerPixel) and it receives each pixel's figure
    /// (rows bottom-up; 0 where no imagery shows or nothing was drawn).
    FrameImages captureImage(LodStrategy& session, const Camera& camera, const TerrainStyle& style,
                             TerrainDrawStats* stats = nullptr,
                             std::vector<float>* imageryTexelsPerPixel = nullptr);

    /// The measures of `lod` against `reference` (same camera); with the previous frame's
    /// captures (same sequence of cameras) also popping. `thresholdPx` (ε) counts the
    /// pixels over it.
    Result<FrameAccuracy> compare(const Camera& camera, const LodCapture& lod,
                                  const ReferenceCapture& reference, double thresholdPx,
                                  const LodCapture* previousLod = nullptr,
                                  const ReferenceCapture* previousReference = nullptr);

    /// captureLod, renderReference and compare for one frame (no popping), thresholdPx =
    /// the session's ε. Past the reference's kDefaultMaxRegions it is not compared.
    Result<FrameAccuracy> measure(LodStrategy& session, const Camera& camera,
                                  const TerrainStyle& style);

    /// The plane's probe's full-resolution surface (TERRAIN_ASSERT: a plane's probe).
    FullResolutionSurface& surface();
    const AccuracyProbeOptions& options() const { return m_options; }
    std::array<std::uint8_t, 3> clearRgb() const;

private:
    AccuracyProbe(std::vector<std::unique_ptr<TruthSurface>> truths, ReferenceRenderer reference,
                  gl::Framebuffer lodTarget, gl::Framebuffer referenceTarget,
                  gl::Framebuffer texelsTarget, const AccuracyProbeOptions& options);

    std::unique_ptr<FullResolutionSurface> m_planeSurface;  // the plane's: its scene and truth
    std::vector<std::unique_ptr<TruthSurface>> m_truths;
    ReferenceRenderer m_reference;
    gl::Framebuffer m_lodTarget;
    gl::Framebuffer m_referenceTarget;
    gl::Framebuffer m_texelsTarget;  // the LOD's, with the imagery's texels per pixel
    AccuracyProbeOptions m_options;
};

}  // namespace terrain::runtime
