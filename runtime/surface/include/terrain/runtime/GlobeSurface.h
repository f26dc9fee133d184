// GlobeSurface: a globe pyramid's surface (Surface.h; DESIGN.md, "The globe"): the six cube
// faces' quadtrees side by side in the layout (io::layoutPatchOf), four children everywhere
// (the pyramid stores those its parent's presentChildren name; the others are drawn from an
// ancestor's tile or as the bare ellipsoid, refined for its curvature down to
// kMaxBareFaceLevel), oriented boxes around the curved patches (globe::patchBounds), and
// Cesium's ellipsoidal occluder as the horizon.
#pragma once

#include "terrain/runtime/Surface.h"

#include <array>

namespace terrain::runtime {

class GlobeSurface final : public Surface {
public:
    /// The deepest face level a patch is split to for the ellipsoid's curvature alone (a
    /// 129-sample patch there is ~15 cm wide).
    static constexpr int kMaxBareFaceLevel = 24;

    /// `manifest` must be a globe pyramid's (manifest.globe set).
    explicit GlobeSurface(const io::PyramidManifest& manifest);

    SurfaceKind kind() const override { return SurfaceKind::Globe; }

    std::span<const io::PatchId> roots() const override { return m_roots; }
    int maxLevel() const override;
    int children(const io::PatchId& id, std::array<SurfaceChild, 4>& out) const override;
    bool storesChild(const io::PatchInfo& parent, int quadrant) const override {
        return ((parent.presentChildren >> quadrant) & 1) != 0;
    }
    bool hasFinerData(const io::PatchId&, const io::PatchInfo& info) const override {
        return info.presentChildren != 0;
    }
    bool drawsBareSurface() const override { return true; }

    double curvatureError(int level) const override;
    std::array<float, 4> curvatureBlockErrors(int level) const override;
    double sampleSpacingM(int level) const override;

    PatchVolume volume(const io::PatchId& id, float minHeight, float maxHeight) const override;
    double distance(const glm::dvec3& point, const PatchVolume& volume) const override;
    SurfaceView view(const Camera& camera) const override;
    bool outsideFrustum(const SurfaceView& view, const PatchVolume& volume,
                        int& planeMask) const override;

    std::uint64_t coverageOf(const io::PatchId& id) const override;
    std::uint64_t wholeCoverage() const override;

private:
    std::array<io::PatchId, 6> m_roots{};
    /// The horizon's ellipsoid lies inside the ground everywhere: below the deepest terrain.
    double m_occluderShrinkM = 0.0;
};

}  // namespace terrain::runtime
