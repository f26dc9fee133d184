// SurfacePlacement: the draw's side of the surface seam (runtime/surface Surface.h): where a
// patch is drawn relative to the camera, in float, without a planet-sized coordinate ever
// reaching the GPU. A frame's placement fills the surface's part of the frame block (the
// plane's anchor sample and DEM extent; the sun; the heights the tint spans) and writes each
// patch's record (PatchInstance): on the plane its north-west DEM sample relative to the
// anchor; on the globe the float reference frame of io/globe SurfaceOffset.h, computed in
// double for the camera. The program of a patch draw is built for its surface
// (TERRAIN_SURFACE_GLOBE: shaders/terrain_surface.glsl).
#pragma once

#include "terrain/cache/GpuTilePool.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/FrameBlock.h"
#include "terrain/runtime/PatchDraw.h"
#include "terrain/runtime/PatchInstance.h"
#include "terrain/runtime/ProgramBuilder.h"
#include "terrain/runtime/Surface.h"
#include "terrain/runtime/TerrainGeometry.h"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <memory>
#include <optional>

namespace terrain::runtime {

/// Render thread only (what beginFrame remembers is the frame's).
class SurfacePlacement {
public:
    /// The placement of `surface` (which must outlive it).
    static std::unique_ptr<SurfacePlacement> forSurface(const Surface& surface);
    virtual ~SurfacePlacement() = default;

    /// Builds the program for this surface: TERRAIN_SURFACE_GLOBE on the globe.
    virtual void defineSurface(ProgramBuilder& builder) const = 0;
    /// Fills the surface's part of `block` for `camera` and remembers what place() needs.
    virtual void beginFrame(const Camera& camera, FrameBlock& block) = 0;
    /// The record of `patch` for this frame's camera. A patch with a tile must be resident
    /// on its layer in `pool` (TERRAIN_ASSERT).
    virtual PatchInstance place(const PatchDraw& patch, const cache::GpuTilePool& pool) const = 0;
    /// Whether the draw may draw distant patches as coarse cells (CoarseCells.h): the plane's
    /// draw so far.
    virtual bool drawsCoarseCells() const = 0;
    /// The plane's geometry, for the coarse cells' choice; null on the globe.
    virtual const TerrainGeometry* planeGeometry() const = 0;
};

/// The plane's placement over `geometry` (which must outlive it).
class PlanePlacement final : public SurfacePlacement {
public:
    explicit PlanePlacement(const TerrainGeometry& geometry) : m_geometry(geometry) {}
    void defineSurface(ProgramBuilder&) const override {}
    void beginFrame(const Camera& camera, FrameBlock& block) override;
    PatchInstance place(const PatchDraw& patch, const cache::GpuTilePool& pool) const override;
    bool drawsCoarseCells() const override { return true; }
    const TerrainGeometry* planeGeometry() const override { return &m_geometry; }
    /// The DEM sample at or before the camera of the last beginFrame, which positions are
    /// relative to.
    glm::dvec2 anchor() const { return m_anchor; }

private:
    const TerrainGeometry& m_geometry;
    glm::dvec2 m_anchor{0.0};  // DEM samples
};

/// The globe's placement of `surface`'s patches and native tiles (the surface must outlive it).
class GlobePlacement final : public SurfacePlacement {
public:
    explicit GlobePlacement(const Surface& surface)
        : m_surface(&surface), m_manifest(surface.manifest()) {}
    /// Face patches of a pyramid of `manifest` only (the reference scenes' frames).
    explicit GlobePlacement(const io::PyramidManifest& manifest) : m_manifest(manifest) {}
    void defineSurface(ProgramBuilder& builder) const override;
    void beginFrame(const Camera& camera, FrameBlock& block) override;
    PatchInstance place(const PatchDraw& patch, const cache::GpuTilePool& pool) const override;
    bool drawsCoarseCells() const override { return false; }
    const TerrainGeometry* planeGeometry() const override { return nullptr; }

private:
    const Surface* m_surface = nullptr;  // null: no native tiles
    const io::PyramidManifest& m_manifest;
    glm::dvec3 m_camera{0.0};
    glm::dvec3 m_cameraUp{0.0};
};

/// The record of a globe patch for a camera at ECEF `camera` whose ellipsoid normal is
/// `cameraUp` (Wgs84::upAt), with its reference point at the camera's nadir clamped to the
/// patch (the globe reference renderer's regions and GlobePrecisionTest write them too).
PatchInstance globePatchInstance(const PatchDraw& patch, const glm::dvec3& camera,
                                 const glm::dvec3& cameraUp, int patchQuads);

/// The record of a native tile (docs/globe.md, "Native leaves") of a grid of `geometry`, for
/// the same camera, its reference point at the camera's nadir clamped to the tile: placed by
/// longitude and latitude (io/globe NativeOffset.h), layerLevel.w 1. A window of the tile
/// (`patch.isVirtual`: runtime/lod NativeWindowTree) keeps the tile's frame, its reference
/// clamped to the window, and maps its samples onto the tile's by texelMap (offset, step, w 2:
/// heights on the source's triangles).
PatchInstance nativeTileInstance(const PatchDraw& patch, const globe::NativeGridGeometry& geometry,
                                 const glm::dvec3& camera, const glm::dvec3& cameraUp);

/// The sun of a globe frame: high over the camera's shoulder, so the place flown over is lit
/// wherever it is (unit length, ECEF axes).
glm::dvec3 globeSunDirection(const Camera& camera);

/// The heights a globe's tint spans: the data's, sea level and 0 included (bare patches are
/// at 0).
std::array<float, 2> globeHeightRange(const io::PyramidManifest& manifest);
/// The sea level a globe pyramid states (ManifestGlobe::seaLevelM), metres; 0 without one.
double globeSeaLevel(const io::PyramidManifest& manifest);

}  // namespace terrain::runtime
