// PlaneSurface: a planar pyramid's surface (Surface.h): one root, children clipped to the
// DEM's extent, every child stored, axis-aligned boxes in the pyramid's map frame
// (TerrainGeometry), no curvature and no horizon.
#pragma once

#include "terrain/runtime/Surface.h"
#include "terrain/runtime/TerrainGeometry.h"

namespace terrain::runtime {

class PlaneSurface final : public Surface {
public:
    explicit PlaneSurface(const io::PyramidManifest& manifest);

    SurfaceKind kind() const override { return SurfaceKind::Plane; }
    const TerrainGeometry& geometry() const { return m_geometry; }

    std::span<const io::PatchId> roots() const override { return {&m_root, 1}; }
    int maxLevel() const override { return layout().finestLevel(); }
    int children(const io::PatchId& id, std::array<SurfaceChild, 4>& out) const override;
    bool storesChild(const io::PatchInfo&, int) const override { return true; }
    bool hasFinerData(const io::PatchId& id, const io::PatchInfo&) const override {
        return id.level < layout().finestLevel();
    }
    bool drawsBareSurface() const override { return false; }

    double flatTriangleError(int, const io::SampleRises&) const override { return 0.0; }
    std::array<float, 4> flatTriangleBlockErrors(int, const io::SampleRises&) const override {
        return {};
    }
    double sampleSpacingM(int level) const override;

    PatchVolume volume(const io::PatchId& id, float minHeight, float maxHeight) const override;
    double distance(const glm::dvec3& point, const PatchVolume& volume) const override;
    bool outsideFrustum(const SurfaceView& view, const PatchVolume& volume,
                        int& planeMask) const override;
    /// Livny et al. 2007's d (Eq. 1): the distance to the nearest edge of V's footprint,
    /// extruded over the DEM's height range (Aabb.h, livnyEdgeDistance).
    double edgeDistance(const glm::dvec3& point, const PatchVolume& volume) const;

    std::uint64_t coverageOf(const io::PatchId& id) const override;
    std::uint64_t wholeCoverage() const override;

private:
    TerrainGeometry m_geometry;
    io::PatchId m_root{0, 0, 0};
};

/// The planar geometry of a plane's surface; `surface` must be a PlaneSurface (the planar
/// programs and methods: TERRAIN_ASSERT).
const TerrainGeometry& planeGeometry(const Surface& surface);

/// The children of `id` inside the layout (1 to 4; fewer at the right and bottom edges).
int containedChildren(const io::PyramidLayout& layout, const io::PatchId& id,
                      io::PatchId (&children)[4]);

/// Finest-level patches under `id` (clipped to the layout): the patch's share of the
/// domain, for checking that selected patches tile it exactly once.
std::uint64_t finestPatchesCovered(const io::PyramidLayout& layout, const io::PatchId& id);

}  // namespace terrain::runtime
