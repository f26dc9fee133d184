// AccuracyProbe: two framebuffers (LOD, reference), the draws into them, the read-backs and
// the measures.
#include "terrain/runtime/AccuracyProbe.h"

#include "terrain/runtime/BoundaryArtefacts.h"

#include "terrain/pyramid/PyramidManifest.h"

#include "terrain/runtime/PlaneReferenceScene.h"
#include "terrain/runtime/PlaneTruth.h"
#include "terrain/runtime/ScreenProjection.h"

#include <epoxy/gl.h>
#include <glm/matrix.hpp>

#include <chrono>
#include <cmath>

namespace terrain::runtime {
namespace {

using Clock = std::chrono::steady_clock;

double millisecondsSince(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

/// Binds `target` and its viewport for the scope; unbinds (framebuffer 0) after.
class TargetScope {
public:
    explicit TargetScope(const gl::Framebuffer& target) {
        glBindFramebuffer(GL_FRAMEBUFFER, target.id());
        glViewport(0, 0, target.width(), target.height());
    }
    ~TargetScope() { glBindFramebuffer(GL_FRAMEBUFFER, 0); }
    TargetScope(const TargetScope&) = delete;
    TargetScope& operator=(const TargetScope&) = delete;
};

}  // namespace

bool FrameAccuracy::finite() const {
    const double figures[] = {error.maxPx,
                              error.meanPx,
                              error.p99Px,
                              error.maxFixedDiagonalPx,
                              error.meanFixedDiagonalPx,
                              error.skirtMaxPx,
                              comparedWithReference ? image.rmse : 0.0,
                              comparedWithReference ? image.psnrDb : 0.0};
    for (const double v : figures) {
        if (!std::isfinite(v)) return false;
    }
    return error.nonFinitePixels == 0;
}

ReferenceStyle referenceStyleOf(const TerrainStyle& style) {
    return {.skyColor = style.skyColor, .fogDensityPerM = style.fogDensityPerM};
}

AccuracyProbe::AccuracyProbe(std::vector<std::unique_ptr<TruthSurface>> truths,
                             ReferenceRenderer reference, gl::Framebuffer lodTarget,
                             gl::Framebuffer referenceTarget, gl::Framebuffer texelsTarget,
                             const AccuracyProbeOptions& options)
    : m_truths(std::move(truths)),
      m_reference(std::move(reference)),
      m_lodTarget(std::move(lodTarget)),
      m_referenceTarget(std::move(referenceTarget)),
      m_texelsTarget(std::move(texelsTarget)),
      m_options(options) {}

Result<std::unique_ptr<AccuracyProbe>> AccuracyProbe::create(
    std::unique_ptr<ReferenceScene> scene, std::vector<std::unique_ptr<TruthSurface>> truths,
    const AccuracyProbeOptions& options) {
    TERRAIN_ASSERT(!truths.empty() && truths.size() <= 2,
                   "AccuracyProbe: one truth, or two (the second for lodError)");
    auto reference = ReferenceRenderer::create(std::move(scene));
    if (!reference) return reference.error();
    auto lodTarget = gl::Framebuffer::create(options.widthPx, options.heightPx, "accuracy LOD");
    if (!lodTarget) return lodTarget.error();
    auto referenceTarget = gl::Framebuffer::createWithFloatAttachment(
        options.widthPx, options.heightPx, "accuracy reference");
    if (!referenceTarget) return referenceTarget.error();
    auto texelsTarget = gl::Framebuffer::createWithFloatAttachment(
        options.widthPx, options.heightPx, "accuracy LOD, imagery texels per pixel");
    if (!texelsTarget) return texelsTarget.error();
    return std::unique_ptr<AccuracyProbe>(new AccuracyProbe(
        std::move(truths), std::move(reference).value(), std::move(lodTarget).value(),
        std::move(referenceTarget).value(), std::move(texelsTarget).value(), options));
}

Result<std::unique_ptr<AccuracyProbe>> AccuracyProbe::create(
    const std::filesystem::path& pyramid, const AccuracyProbeOptions& options,
    const std::filesystem::path& referencePyramid) {
    if (!referencePyramid.empty()) {
        auto measured = io::readManifest(pyramid);
        if (!measured) return measured.error();
        auto truth = io::readManifest(referencePyramid);
        if (!truth) return truth.error();
        if (!(truth.value().layout == measured.value().layout) ||
            !(truth.value().georeference == measured.value().georeference) ||
            truth.value().globe.has_value() != measured.value().globe.has_value())
            return Error{referencePyramid.string() + ": the reference pyramid has not " +
                         pyramid.string() + "'s layout and georeference"};
    }
    auto opened = FullResolutionSurface::open(referencePyramid.empty() ? pyramid : referencePyramid,
                                              options.surfaceBudgetBytes);
    if (!opened) return opened.error();
    auto surface = std::make_unique<FullResolutionSurface>(std::move(opened).value());
    std::vector<std::unique_ptr<TruthSurface>> truths;
    truths.push_back(std::make_unique<PlaneTruth>(*surface));
    auto probe =
        create(std::make_unique<PlaneReferenceScene>(*surface), std::move(truths), options);
    if (!probe) return probe.error();
    probe.value()->m_planeSurface = std::move(surface);
    return probe;
}

FullResolutionSurface& AccuracyProbe::surface() {
    TERRAIN_ASSERT(m_planeSurface != nullptr, "AccuracyProbe::surface: not a plane's probe");
    return *m_planeSurface;
}

std::array<std::uint8_t, 3> AccuracyProbe::clearRgb() const {
    std::array<std::uint8_t, 3> rgb{};
    for (std::size_t c = 0; c < 3; ++c) {
        rgb[c] = static_cast<std::uint8_t>(std::lround(m_options.clearColor[c] * 255.0f));
    }
    return rgb;
}

Result<ReferenceCapture> AccuracyProbe::renderReference(const Camera& camera,
                                                        const ReferenceStyle& style) {
    TERRAIN_ASSERT(
        camera.viewportWidth == m_options.widthPx && camera.viewportHeight == m_options.heightPx,
        "AccuracyProbe: the camera's viewport is not the probe's");
    ReferenceCapture capture;
    m_referenceTarget.clear(m_options.clearColor, 0.0f);  // reversed Z: far is 0
    m_referenceTarget.clearFloatAttachment(std::numeric_limits<float>::quiet_NaN());
    {
        const TargetScope scope(m_referenceTarget);
        const auto start = Clock::now();
        auto drawn = m_reference.draw(camera, style);
        if (!drawn) return drawn.error();
        glFinish();
        capture.drawMs = millisecondsSince(start);
        capture.draw = drawn.value();
    }
    capture.images = readFrameImages(m_referenceTarget);
    return capture;
}

LodCapture AccuracyProbe::captureLod(LodStrategy& session, const Camera& camera,
                                     const TerrainStyle& style) {
    TERRAIN_ASSERT(
        camera.viewportWidth == m_options.widthPx && camera.viewportHeight == m_options.heightPx,
        "AccuracyProbe: the camera's viewport is not the probe's");
    LodCapture capture;
    m_lodTarget.clear(m_options.clearColor, 0.0f);
    {
        const TargetScope scope(m_lodTarget);
        const auto start = Clock::now();
        capture.draw = session.draw(camera, style);
        glFinish();
        capture.drawMs = millisecondsSince(start);
    }
    capture.images = readFrameImages(m_lodTarget);
    // A method without skirts draws the same frame again without them: nothing to tell apart.
    if (style.skirts && lodMethodInfo(session.method()).skirts) {
        TerrainStyle withoutSkirts = style;
        withoutSkirts.skirts = false;
        withoutSkirts.measure = false;
        m_lodTarget.clear(m_options.clearColor, 0.0f);
        {
            const TargetScope scope(m_lodTarget);
            session.draw(camera, withoutSkirts);
        }
        capture.depthWithoutSkirts = m_lodTarget.readDepth();
    }
    if (style.debugView == TerrainDebugView::Shaded && lodMethodInfo(session.method()).patchIds) {
        TerrainStyle patches = style;
        patches.debugView = TerrainDebugView::PatchId;
        patches.measure = false;
        m_lodTarget.clear({0.0f, 0.0f, 0.0f, 0.0f}, 0.0f);
        {
            const TargetScope scope(m_lodTarget);
            session.draw(camera, patches);
        }
        capture.patchIds = patchIdsOf(m_lodTarget.readColorRgba8());
    }
    return capture;
}

FrameImages AccuracyProbe::captureImage(LodStrategy& session, const Camera& camera,
                                        const TerrainStyle& style, TerrainDrawStats* stats,
                                        std::vector<float>* imageryTexelsPerPixel) {
    TERRAIN_ASSERT(
        camera.viewportWidth == m_options.widthPx && camera.viewportHeight == m_options.heightPx,
        "AccuracyProbe: the camera's viewport is not the probe's");
    // The variant writes its figure at output 1: a target with an R32F attachment there.
    TerrainStyle drawn = style;
    drawn.imageryTexelsPerPixel = imageryTexelsPerPixel != nullptr;
    gl::Framebuffer& target = drawn.imageryTexelsPerPixel ? m_texelsTarget : m_lodTarget;
    target.clear(m_options.clearColor, 0.0f);
    if (drawn.imageryTexelsPerPixel) target.clearFloatAttachment(0.0f);
    {
        const TargetScope scope(target);
        const TerrainDrawStats drawnStats = session.draw(camera, drawn);
        if (stats != nullptr) *stats = drawnStats;
    }
    FrameImages images = readFrameImages(target);
    // readFrameImages takes a float attachment for a reference's heights: here it is not.
    if (imageryTexelsPerPixel != nullptr) *imageryTexelsPerPixel = std::move(images.heightM);
    images.heightM.clear();
    return images;
}

Result<FrameAccuracy> AccuracyProbe::compare(const Camera& camera, const LodCapture& lod,
                                             const ReferenceCapture& reference, double thresholdPx,
                                             const LodCapture* previousLod,
                                             const ReferenceCapture* previousReference) {
    FrameAccuracy a;
    a.comparedWithReference = reference.draw.complete;
    // A partial reference image says nothing of the pixels it left out: the error is then
    // measured over every drawn pixel, and the images are not compared.
    const std::span<const float> referenceDepth =
        a.comparedWithReference ? std::span<const float>(reference.images.depth)
                                : std::span<const float>();
    for (std::size_t t = 0; t < m_truths.size(); ++t) {
        auto error = measureScreenSpaceError(camera, lod.images.depth, lod.depthWithoutSkirts,
                                             referenceDepth, *m_truths[t], thresholdPx);
        if (!error) return error.error();
        if (t == 0) {
            a.error = std::move(error).value();
        } else {
            a.lodError = std::move(error).value();
        }
    }
    if (!a.comparedWithReference) return a;
    a.image = compareImages(lod.images.rgba, reference.images.rgba);
    const UncoveredPixels uncovered =
        countUncoveredPixels(lod.images, reference.images, clearRgb());
    // The reference splits every cell along one diagonal; the LOD's tessellator chooses its
    // own. On cells steep enough that the two are pixels apart, that choice decides which
    // pixel centres are covered, so a clear pixel is a crack only if every choice covers it.
    // And the LOD may lie up to ε pixels below the truth: where the ray grazes the truth
    // (a sky sliver between needles, narrower than a pixel, whose tip then reaches a pixel
    // further) it is a crack only if the truth lowered that much still covers it. ε pixels
    // of height seen square-on at distance D are ε · D · (the pixel's angle) metres; seen
    // obliquely they are more, so this lowers the truth by the least the bound allows.
    const glm::dmat4 inverse = glm::inverse(camera.relativeViewProjection());
    const auto w = static_cast<std::size_t>(camera.viewportWidth);
    const double lowerPerMetre =
        thresholdPx * 2.0 * std::tan(0.5 * camera.fovY) / double(camera.viewportHeight);
    for (const std::size_t i : uncovered.cracks) {
        const glm::dvec3 along =
            unprojectPixel(inverse, camera.viewportWidth, camera.viewportHeight,
                           static_cast<int>(i % w), static_cast<int>(i / w), 0.5f);
        auto covered =
            m_truths.front()->everyTriangulationCovers(camera.position, along, lowerPerMetre);
        if (!covered) return covered.error();
        if (covered.value()) {
            a.cracks.push_back(i);
        } else {
            ++a.diagonalUncoveredPixels;
        }
    }
    a.uncoveredPixels = uncovered.uncovered;
    // The LOD may draw any surface up to ε pixels off the reference's.
    const int shiftPx = static_cast<int>(std::ceil(thresholdPx));
    a.overdrawnPixels = countOverdrawnPixels(lod.images, reference.images, shiftPx);
    if (!lod.patchIds.empty()) {
        BoundaryArtefacts found =
            findBoundaryArtefacts(lod.images, lod.patchIds, reference.images, shiftPx);
        a.boundaryArtefacts = std::move(found.pixels);
        a.boundaryArtefactPixels = a.boundaryArtefacts.size();
        a.boundarySilhouettePixels = found.silhouettePixels;
        a.boundaryShading = measureBoundaryShading(lod.images, lod.patchIds, reference.images);
    }
    for (std::size_t i = 0; i < reference.images.pixels(); ++i) {
        a.referencePixels += reference.images.drawn(i) ? 1 : 0;
        a.lodPixels += lod.images.drawn(i) ? 1 : 0;
    }
    if (previousLod != nullptr && previousReference != nullptr &&
        previousReference->draw.complete) {
        a.lodChangeLevels = meanImageChange(previousLod->images.rgba, lod.images.rgba);
        a.referenceChangeLevels =
            meanImageChange(previousReference->images.rgba, reference.images.rgba);
        a.poppingLevels = poppingLevels(previousLod->images.rgba, lod.images.rgba,
                                        previousReference->images.rgba, reference.images.rgba);
    }
    return a;
}

Result<FrameAccuracy> AccuracyProbe::measure(LodStrategy& session, const Camera& camera,
                                             const TerrainStyle& style) {
    const LodCapture lod = captureLod(session, camera, style);
    auto reference = renderReference(camera, referenceStyleOf(style));
    if (!reference) return reference.error();
    return compare(camera, lod, reference.value(), session.errorPx());
}

}  // namespace terrain::runtime
