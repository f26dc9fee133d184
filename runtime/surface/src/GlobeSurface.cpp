// GlobeSurface: the cube faces' quadtrees in the layout, oriented boxes, the ellipsoid's
// curvature, the horizon.
#include "terrain/runtime/GlobeSurface.h"

#include "terrain/base/Assert.h"
#include "terrain/pyramid/GlobeLayout.h"
#include "terrain/runtime/GlobeFrustum.h"

#include <algorithm>

namespace terrain::runtime {
namespace {

// A patch's share of GlobeSurface::coverageOf: face level l counts 4^(30 − l).
constexpr int kCoverageLevels = 30;

}  // namespace

GlobeSurface::GlobeSurface(const io::PyramidManifest& manifest)
    : Surface(manifest), m_occluderShrinkM(std::max(0.0, -manifest.statistics.minHeight) + 1.0) {
    TERRAIN_ASSERT(manifest.globe.has_value(), "GlobeSurface needs a globe pyramid");
    TERRAIN_ASSERT(manifest.globe->faceFinestLevel <= io::kMaxGlobeFaceLevel,
                   "readManifest refuses deeper globe pyramids");
    for (int face = 0; face < globe::kCubeFaces; ++face)
        m_roots[static_cast<std::size_t>(face)] = io::layoutPatchOf({face, 0, 0, 0});
}

int GlobeSurface::maxLevel() const {
    return std::min(kMaxBareFaceLevel, io::kMaxGlobeFaceLevel) + io::ManifestGlobe::kLevelOffset;
}

int GlobeSurface::children(const io::PatchId& id, std::array<SurfaceChild, 4>& out) const {
    const globe::GlobePatchId g = io::globePatchOf(id);
    for (int c = 0; c < 4; ++c) {
        const globe::GlobePatchId child{g.face, g.level + 1, 2 * g.x + (c & 1), 2 * g.y + (c >> 1)};
        out[static_cast<std::size_t>(c)] = {io::layoutPatchOf(child), c};
    }
    return 4;
}

double GlobeSurface::curvatureError(int level) const {
    return globe::flatTriangleErrorBound(sampleSpacingM(level));
}

std::array<float, 4> GlobeSurface::curvatureBlockErrors(int level) const {
    const double spacing = sampleSpacingM(level);
    std::array<float, 4> errors{};
    for (int d = 0; d < 4; ++d)
        errors[static_cast<std::size_t>(d)] =
            static_cast<float>(globe::flatTriangleErrorBound(spacing * double(2 << d)));
    return errors;
}

double GlobeSurface::sampleSpacingM(int level) const {
    return globe::maxSampleSpacing(level - io::ManifestGlobe::kLevelOffset, layout().patchQuads());
}

PatchVolume GlobeSurface::volume(const io::PatchId& id, float minHeight, float maxHeight) const {
    return globe::patchBounds(io::globePatchOf(id), minHeight, maxHeight);
}

double GlobeSurface::distance(const glm::dvec3& point, const PatchVolume& volume) const {
    return globe::distanceToBox(point, std::get<globe::OrientedBox>(volume));
}

SurfaceView GlobeSurface::view(const Camera& camera) const {
    SurfaceView view = Surface::view(camera);
    view.horizon.emplace(m_occluderShrinkM);
    view.horizon->setCamera(camera.position);
    return view;
}

bool GlobeSurface::outsideFrustum(const SurfaceView& view, const PatchVolume& volume,
                                  int& /*planeMask*/) const {
    return !frustumMeetsBox(view.frustum, std::get<globe::OrientedBox>(volume));
}

std::uint64_t GlobeSurface::coverageOf(const io::PatchId& id) const {
    const int faceLevel = id.level - io::ManifestGlobe::kLevelOffset;
    return std::uint64_t{1} << (2 * (kCoverageLevels - faceLevel));
}

std::uint64_t GlobeSurface::wholeCoverage() const {
    return std::uint64_t{6} << (2 * kCoverageLevels);
}

}  // namespace terrain::runtime
