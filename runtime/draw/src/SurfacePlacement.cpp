// SurfacePlacement: the plane's anchor sample and the globe's reference frames.
#include "terrain/runtime/SurfacePlacement.h"

#include "terrain/base/Assert.h"
#include "terrain/globe/NativeOffset.h"
#include "terrain/globe/SurfaceOffset.h"
#include "terrain/globe/Wgs84.h"
#include "terrain/pyramid/GlobeLayout.h"
#include "terrain/runtime/PlaneSurface.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace terrain::runtime {
namespace {

/// Towards the sun over the plane, unit length, world frame (x east, y north, z up): from the
/// north-west, 33° above the horizon, the classic hillshade light.
constexpr std::array<float, 4> kPlaneSun{-0.5345f, 0.6414f, 0.5505f, 0.0f};

// texelMap.w of a native window (shaders/terrain_heights.glsl, tileHeight's modes): its heights
// on the source's own triangles between the tile's samples.
constexpr float kHeightsOnTriangles = 2.0f;

std::array<float, 2> floats(const glm::dvec2& v) {
    return {static_cast<float>(v.x), static_cast<float>(v.y)};
}

// Metres per tile sample along s and t at patch coordinates (u, v), for the shading normal:
// a patch sample's spacing over `texelStep` (tile samples per patch sample). The difference
// is taken over the part of u ± kStep (v ± kStep) inside the patch and divided by that part's
// length: (u, v) is the patch's point nearest the camera, on its edge for every patch the
// camera is not above, and a central quotient clamped there measured half a step over a whole
// one, halving the spacing and doubling every slope of the patch (a shading seam along the
// edges of the patches ahead of the camera, issue 46).
std::array<float, 4> sampleSpacing(const globe::GlobePatchId& id, int quads, double u, double v,
                                   double texelStep) {
    constexpr double kStep = 1e-3;
    const auto at = [&](double pu, double pv) {
        const globe::FacePoint p = globe::patchPoint(id, pu, pv);
        return globe::Wgs84::pointAlongNormal(globe::directionOf(p.face, p.s, p.t), 0.0);
    };
    const auto metresPerSample = [&](double from, double to, const glm::dvec3& a,
                                     const glm::dvec3& b) {
        return glm::distance(a, b) / (to - from) / quads / texelStep;
    };
    const double u0 = std::max(u - kStep, 0.0), u1 = std::min(u + kStep, 1.0);
    const double v0 = std::max(v - kStep, 0.0), v1 = std::min(v + kStep, 1.0);
    const double du = metresPerSample(u0, u1, at(u0, v), at(u1, v));
    const double dv = metresPerSample(v0, v1, at(u, v0), at(u, v1));
    return {static_cast<float>(du), static_cast<float>(dv), 0.0f, 0.0f};
}

}  // namespace

std::unique_ptr<SurfacePlacement> SurfacePlacement::forSurface(const Surface& surface) {
    if (surface.kind() == SurfaceKind::Globe) return std::make_unique<GlobePlacement>(surface);
    return std::make_unique<PlanePlacement>(runtime::planeGeometry(surface));
}

// Positions reach the GPU as DEM samples relative to the anchor, the DEM sample at or before
// the camera: integers, exact in float near the camera (terrainPositionM).
void PlanePlacement::beginFrame(const Camera& camera, FrameBlock& block) {
    const io::PyramidLayout& layout = m_geometry.layout();
    const glm::dvec2 cameraSample = m_geometry.sampleOfWorld(camera.position.x, camera.position.y);
    m_anchor = glm::floor(cameraSample);
    const glm::dvec2 lastSample{static_cast<double>(layout.rasterWidth() - 1),
                                static_cast<double>(layout.rasterHeight() - 1)};
    const std::array<float, 2> fraction = floats(cameraSample - m_anchor);
    block.planeCamera = {fraction[0], fraction[1], static_cast<float>(camera.position.z), 0.0f};
    const std::array<float, 2> spacing = floats(m_geometry.sampleSpacing());
    block.planeSpacing = {spacing[0], spacing[1], 0.0f, 0.0f};
    const std::array<float, 2> first = floats(-m_anchor);
    const std::array<float, 2> last = floats(lastSample - m_anchor);
    block.demExtent = {first[0], first[1], last[0], last[1]};
    block.sunDirection = kPlaneSun;
    block.heightRange = {static_cast<float>(m_geometry.minHeight()),
                         static_cast<float>(m_geometry.maxHeight()), 0.0f, 0.0f};
}

PatchInstance PlanePlacement::place(const PatchDraw& p, const cache::GpuTilePool& pool) const {
    TERRAIN_ASSERT(pool.isResident(p.id) && pool.layerOf(p.id) == p.layer,
                   "drawing a patch that is not resident on its layer");
    const io::PyramidLayout& layout = m_geometry.layout();
    const io::PatchInfo& info = *pool.info(p.id);
    const std::int64_t step = layout.levelStep(p.id.level);
    // Double → float only after subtracting the anchor.
    const double originX = static_cast<double>(layout.patchOriginX(p.id) * step) - m_anchor.x;
    const double originY = static_cast<double>(layout.patchOriginY(p.id) * step) - m_anchor.y;
    PatchInstance record;
    record.placement0 = {static_cast<float>(originX), static_cast<float>(originY),
                         static_cast<float>(step), 0.0f};
    record.errors = {p.errorM, p.skirtDepthM, info.minHeight, info.maxHeight};
    record.texelMap = {0.0f, 0.0f, 1.0f, 0.0f};
    record.layerLevel = {p.layer, p.id.level, static_cast<std::int32_t>(p.id.x),
                         static_cast<std::int32_t>(p.id.y)};
    return record;
}

void GlobePlacement::defineSurface(ProgramBuilder& builder) const {
    builder.define("TERRAIN_SURFACE_GLOBE");
}

void GlobePlacement::beginFrame(const Camera& camera, FrameBlock& block) {
    m_camera = camera.position;
    m_cameraUp = globe::Wgs84::upAt(camera.position);
    // The globe has no edge to clip: shaders/terrain.frag keeps everything.
    block.demExtent = {-1e30f, -1e30f, 1e30f, 1e30f};
    const glm::dvec3 sun = globeSunDirection(camera);
    block.sunDirection = {static_cast<float>(sun.x), static_cast<float>(sun.y),
                          static_cast<float>(sun.z), 0.0f};
    const std::array<float, 2> range = globeHeightRange(m_manifest);
    // The sea at the level the sources state (their zero, mean sea level, for SRTM and
    // ETOPO), drawn as water.
    block.heightRange = {range[0], range[1], static_cast<float>(globeSeaLevel(m_manifest)), 1.0f};
}

PatchInstance GlobePlacement::place(const PatchDraw& p, const cache::GpuTilePool& pool) const {
    TERRAIN_ASSERT(p.layer < 0 || pool.layerOf(p.tileId) == p.layer,
                   "drawing a data patch that is not resident on its layer");
    if (const globe::NativeGridGeometry* native =
            m_surface != nullptr ? m_surface->nativeGeometry(p.id) : nullptr)
        return nativeTileInstance(p, *native, m_camera, m_cameraUp);
    return globePatchInstance(p, m_camera, m_cameraUp, m_manifest.layout.patchQuads());
}

PatchInstance nativeTileInstance(const PatchDraw& p, const globe::NativeGridGeometry& geometry,
                                 const glm::dvec3& camera, const glm::dvec3& cameraUp) {
    // A window of the tile (runtime/lod NativeWindowTree) is drawn in the tile's frame, its
    // reference kept inside the window so that the stage's differences stay small.
    globe::NativeWindow window;
    if (p.isVirtual) {
        window.depth = -std::ilogb(p.texelStep);
        const double samples = double(geometry.quads) * double(p.texelStep);
        window.i = static_cast<std::int64_t>(std::lround(double(p.texelOffset[0]) / samples));
        window.j = static_cast<std::int64_t>(std::lround(double(p.texelOffset[1]) / samples));
    }
    const glm::dvec2 uv0 =
        globe::nearestNativeCoordinates(geometry, p.id.x, p.id.y, cameraUp, window);
    const globe::NativeSurfaceFrame f =
        globe::makeNativeSurfaceFrame(geometry, p.id.x, p.id.y, uv0.x, uv0.y, camera);
    PatchInstance record;
    record.placement0 = {f.lonPerU, f.u0, f.v0, f.lon0};
    // Where its imagery lies on the face patch it drapes (surface_globe.glsl, nativeImageryUv).
    const globe::NativeImageryFrame imagery = globe::makeNativeImageryFrame(
        geometry, p.id.x, p.id.y, f, io::globePatchOf(p.imageryPatch));
    record.placement1 = {f.lat0, f.latPerV, imagery.u0, imagery.v0};
    record.placement2 = {f.direction0.x, f.direction0.y, f.direction0.z, f.sqrtG0};
    record.placement3 = {f.originFromCamera.x, f.originFromCamera.y, f.originFromCamera.z,
                         f.primeVertical0};
    // Metres per tile sample east and south at the reference point (for the shading normal).
    const globe::CurvatureRadii radii =
        globe::Wgs84::curvatureRadiiAt(f.lat0 * 180.0 / std::numbers::pi);
    const double radian = std::numbers::pi / 180.0;
    // w: 1 / quads, which takes texelMap's offset from tile samples to tile coordinates.
    record.placement4 = {static_cast<float>(radii.primeVertical * std::cos(double(f.lat0)) *
                                            geometry.pixelLonDeg * radian),
                         static_cast<float>(radii.meridian * geometry.pixelLatDeg * radian),
                         imagery.uPerAlpha, 1.0f / static_cast<float>(geometry.quads)};
    record.errors = {p.errorM, p.skirtDepthM, p.minHeight, p.maxHeight};
    record.bareBlockErrors = p.bareBlockErrorsM;
    // A window's heights lie on the source's own triangles between the tile's samples
    // (shaders/terrain_heights.glsl, mode 2); the whole tile's are its samples.
    record.texelMap = {p.texelOffset[0], p.texelOffset[1], p.texelStep,
                       p.isVirtual ? kHeightsOnTriangles : 0.0f};
    record.layerLevel = {p.layer, p.id.level, imagery.face, 1};
    record.nativeCells = {static_cast<std::int32_t>(p.nativeCells & 0xffffffffu),
                          static_cast<std::int32_t>(p.nativeCells >> 32), p.nativeWindow[0],
                          p.nativeWindow[1]};
    return record;
}

PatchInstance globePatchInstance(const PatchDraw& p, const glm::dvec3& camera,
                                 const glm::dvec3& cameraUp, int patchQuads) {
    const globe::GlobePatchId id = io::globePatchOf(p.id);
    const glm::dvec2 uv0 = globe::nearestPatchCoordinates(id, cameraUp);
    const globe::PatchSurfaceFrame f = globe::makePatchSurfaceFrame(id, uv0.x, uv0.y, camera);
    PatchInstance record;
    record.placement0 = {f.alphaPerU, f.u0, f.v0, f.alpha0};
    record.placement1 = {f.beta0, f.cubeS0, f.cubeT0, f.inverseLength0};
    record.placement2 = {f.direction0.x, f.direction0.y, f.direction0.z, f.sqrtG0};
    record.placement3 = {f.originFromCamera.x, f.originFromCamera.y, f.originFromCamera.z,
                         f.primeVertical0};
    record.placement4 = sampleSpacing(id, patchQuads, uv0.x, uv0.y, p.texelStep);
    record.errors = {p.errorM, p.skirtDepthM, p.minHeight, p.maxHeight};
    record.bareBlockErrors = p.bareBlockErrorsM;
    record.texelMap = {p.texelOffset[0], p.texelOffset[1], p.texelStep, p.isVirtual ? 1.0f : 0.0f};
    record.layerLevel = {p.layer, id.level, id.face, 0};
    return record;
}

glm::dvec3 globeSunDirection(const Camera& camera) {
    const glm::dvec3 up = globe::Wgs84::upAt(camera.position);
    return glm::normalize(2.0 * up + camera.right() - 0.5 * camera.forward());
}

double globeSeaLevel(const io::PyramidManifest& manifest) {
    return manifest.globe ? manifest.globe->seaLevelM : 0.0;
}

std::array<float, 2> globeHeightRange(const io::PyramidManifest& manifest) {
    const double sea = globeSeaLevel(manifest);
    return {static_cast<float>(std::min({manifest.statistics.minHeight, 0.0, sea})),
            static_cast<float>(std::max({manifest.statistics.maxHeight, 1.0, sea + 1.0}))};
}

}  // namespace terrain::runtime
