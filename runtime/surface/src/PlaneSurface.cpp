// PlaneSurface: boxes from TerrainGeometry, children clipped to the layout, the frustum test
// with the plane masks of nested boxes.
#include "terrain/runtime/PlaneSurface.h"

#include "terrain/base/Assert.h"

#include <algorithm>

namespace terrain::runtime {

int containedChildren(const io::PyramidLayout& layout, const io::PatchId& id,
                      io::PatchId (&children)[4]) {
    int count = 0;
    for (int dy = 0; dy < 2; ++dy) {
        for (int dx = 0; dx < 2; ++dx) {
            const io::PatchId child{id.level + 1, 2 * id.x + dx, 2 * id.y + dy};
            if (layout.contains(child)) children[count++] = child;
        }
    }
    return count;
}

std::uint64_t finestPatchesCovered(const io::PyramidLayout& layout, const io::PatchId& id) {
    const int finest = layout.finestLevel();
    const std::int64_t scale = std::int64_t{1} << (finest - id.level);
    const std::int64_t x0 = id.x * scale, y0 = id.y * scale;
    const std::int64_t x1 = std::min(layout.patchesX(finest), x0 + scale);
    const std::int64_t y1 = std::min(layout.patchesY(finest), y0 + scale);
    return static_cast<std::uint64_t>(std::max<std::int64_t>(0, x1 - x0)) *
           static_cast<std::uint64_t>(std::max<std::int64_t>(0, y1 - y0));
}

const TerrainGeometry& planeGeometry(const Surface& surface) {
    TERRAIN_ASSERT(surface.kind() == SurfaceKind::Plane, "planeGeometry: a globe's surface");
    return static_cast<const PlaneSurface&>(surface).geometry();
}

PlaneSurface::PlaneSurface(const io::PyramidManifest& manifest)
    : Surface(manifest), m_geometry(manifest) {
    TERRAIN_ASSERT(!manifest.globe.has_value(), "PlaneSurface: a globe pyramid");
}

int PlaneSurface::children(const io::PatchId& id, std::array<SurfaceChild, 4>& out) const {
    int count = 0;
    for (int dy = 0; dy < 2; ++dy) {
        for (int dx = 0; dx < 2; ++dx) {
            const io::PatchId child{id.level + 1, 2 * id.x + dx, 2 * id.y + dy};
            if (layout().contains(child))
                out[static_cast<std::size_t>(count++)] = {child, dy * 2 + dx};
        }
    }
    return count;
}

double PlaneSurface::sampleSpacingM(int level) const {
    const glm::dvec2 spacing =
        m_geometry.sampleSpacing() * static_cast<double>(layout().levelStep(level));
    return std::max(spacing.x, spacing.y);
}

PatchVolume PlaneSurface::volume(const io::PatchId& id, float minHeight, float maxHeight) const {
    io::PatchInfo heights;
    heights.minHeight = minHeight;
    heights.maxHeight = maxHeight;
    return m_geometry.patchBounds(id, heights);
}

double PlaneSurface::distance(const glm::dvec3& point, const PatchVolume& volume) const {
    return distanceToBox(point, std::get<Aabb>(volume));
}

double PlaneSurface::edgeDistance(const glm::dvec3& point, const PatchVolume& volume) const {
    return livnyEdgeDistance(point, std::get<Aabb>(volume), m_geometry.minHeight(),
                             m_geometry.maxHeight());
}

bool PlaneSurface::outsideFrustum(const SurfaceView& view, const PatchVolume& volume,
                                  int& planeMask) const {
    const Aabb& box = std::get<Aabb>(volume);
    for (int p = 0; p < 5; ++p) {
        if ((planeMask & (1 << p)) == 0) continue;
        const glm::dvec4& plane = view.frustum.planes[static_cast<std::size_t>(p)];
        const glm::dvec3 far{plane.x >= 0.0 ? box.max.x : box.min.x,
                             plane.y >= 0.0 ? box.max.y : box.min.y,
                             plane.z >= 0.0 ? box.max.z : box.min.z};
        if (plane.x * far.x + plane.y * far.y + plane.z * far.z + plane.w < 0.0) return true;
        const glm::dvec3 near{plane.x >= 0.0 ? box.min.x : box.max.x,
                              plane.y >= 0.0 ? box.min.y : box.max.y,
                              plane.z >= 0.0 ? box.min.z : box.max.z};
        // Wholly inside this plane: so are the children's boxes, which nest in this one.
        if (plane.x * near.x + plane.y * near.y + plane.z * near.z + plane.w >= 0.0)
            planeMask &= ~(1 << p);
    }
    return false;
}

std::uint64_t PlaneSurface::coverageOf(const io::PatchId& id) const {
    return finestPatchesCovered(layout(), id);
}

std::uint64_t PlaneSurface::wholeCoverage() const { return finestPatchesCovered(layout(), m_root); }

}  // namespace terrain::runtime
