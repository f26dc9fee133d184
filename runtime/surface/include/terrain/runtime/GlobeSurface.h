// GlobeSurface: a globe pyramid's surface (Surface.h; DESIGN.md, "The globe"): the six cube
// faces' quadtrees side by side in the layout (io::layoutPatchOf), four children everywhere
// (the pyramid stores those its parent's presentChildren name; the others are drawn from an
// ancestor's tile or as the bare ellipsoid, refined for its curvature down to
// kMaxBareFaceLevel), oriented boxes around the curved patches (globe::patchBounds), and
// Cesium's ellipsoidal occluder as the horizon.
#pragma once

#include "terrain/runtime/Surface.h"

#include <array>
#include <optional>
#include <span>
#include <vector>

namespace terrain::runtime {

class GlobeSurface final : public Surface {
public:
    /// The deepest face level a patch is split to for the ellipsoid's curvature alone (a
    /// 129-sample patch there is ~15 cm wide).
    static constexpr int kMaxBareFaceLevel = 24;

    /// A patch's native tiles are at most this many (a grid coarser for it has none).
    static constexpr int kMaxNativeTilesPerPatch = 16;
    /// A native grid's samples may be this many times as far apart as the patch's at most
    /// (the finest face level is as fine as a source at its centre, so up to √2 × 2 over a face
    /// and its latitudes).
    static constexpr double kMaxNativeSpacingRatio = 4.0;

    /// `manifest` must be a globe pyramid's (manifest.globe set); `nativeGrids` its native
    /// grids (io::readNativeGridManifests).
    explicit GlobeSurface(const io::PyramidManifest& manifest,
                          std::span<const io::NativeGridManifest> nativeGrids = {});

    SurfaceKind kind() const override { return SurfaceKind::Globe; }

    /// A box of longitudes (west ≤ east, maybe past ±180°) and latitudes, degrees.
    struct LonLatBox {
        double west = 0.0, east = 0.0, south = 0.0, north = 0.0;
    };

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

    double flatTriangleError(int level, const io::SampleRises& rises) const override;
    std::array<float, 4> flatTriangleBlockErrors(int level,
                                                 const io::SampleRises& rises) const override;
    double sampleSpacingM(int level) const override;

    PatchVolume volume(const io::PatchId& id, float minHeight, float maxHeight) const override;
    double distance(const glm::dvec3& point, const PatchVolume& volume) const override;
    SurfaceView view(const Camera& camera) const override;
    bool outsideFrustum(const SurfaceView& view, const PatchVolume& volume,
                        int& planeMask) const override;

    std::uint64_t coverageOf(const io::PatchId& id) const override;
    std::uint64_t wholeCoverage() const override;

    bool nativeTilesOver(const io::PatchId& id, std::vector<io::PatchId>& out) const override;
    PatchVolume nativeTileVolume(const io::PatchId& tile, float minHeight, float maxHeight,
                                 const globe::NativeWindow& window) const override;
    NativeGeometricErrors nativeGeometricErrors(const io::PatchId& tile, const io::PatchInfo& info,
                                                const io::SampleRises& rises,
                                                const globe::NativeWindow& window) const override;
    bool nativeGroundIsPure(const io::PatchId& id) const override;
    std::optional<glm::dvec4> nativeFootprintOn(const io::PatchId& id,
                                                const io::PatchId& tile) const override;
    bool nativeWindowIsPure(const io::PatchId& tile,
                            const globe::NativeWindow& window) const override;
    std::optional<NativeTilePoint> nativeTileUnder(const glm::dvec3& up, int level) const override;
    const globe::NativeGridGeometry* nativeGeometry(const io::PatchId& tile) const override;

private:
    /// The largest angle between neighbouring samples of `level` (globe::maxSampleAngle).
    double sampleAngle(int level) const;
    /// A native grid as the LOD and the draw need it: where its sample centres reach
    /// (degrees; longitudes as its georeference runs, maybe past ±180°), its tiles, and how far
    /// apart its samples lie at most.
    struct NativeGrid {
        int source = 0;
        globe::NativeGridGeometry geometry;
        std::int64_t tilesX = 0, tilesY = 0;
        std::int64_t lastColumn = 0, lastRow = 0;  // of its raster
        double firstLon = 0.0, lastLon = 0.0, northLat = 0.0, southLat = 0.0;
        double spacingM = 0.0;
        /// Where its source lies (ManifestGlobeSource), shrunk by its seam band's widest and a
        /// sample; and the finer sources' extents, grown by one of its samples: outside those,
        /// and inside this, only its own samples show. Empty `inside`: unknown, never pure.
        std::optional<LonLatBox> inside;
        std::vector<LonLatBox> finer;

        /// The whole turns to add to a longitude to bring it nearest the grid's middle (a
        /// grid may run past ±180°).
        double turnsToward(double longitudeDeg) const;
        /// A place's sample coordinates on the grid (sample centres at whole numbers), its
        /// longitude already brought near the grid (turnsToward).
        double columnAt(double longitudeDeg) const {
            return (longitudeDeg - geometry.westDeg) / geometry.pixelLonDeg - 0.5;
        }
        double rowAt(double latitudeDeg) const {
            return (geometry.northDeg - latitudeDeg) / geometry.pixelLatDeg - 0.5;
        }
        /// Whether the box lies within the grid's raster (its longitudes brought near it).
        bool holds(double west, double east, double south, double north) const {
            return west >= firstLon && east <= lastLon && south >= southLat && north <= northLat;
        }
    };
    const NativeGrid* nativeGridOf(const io::PatchId& tile) const;
    static void setPurity(NativeGrid& grid, const io::ManifestGlobe& globe);
    /// Whether `grid`'s samples alone show over `box` (nativeWindowIsPure's rule).
    static bool isPure(const NativeGrid& grid, const LonLatBox& box);
    /// nativeTilesOver's choice: the grid whose tiles stand for `id` (appended to `out`) and
    /// the patch's footprint on it (its longitudes brought near the grid's); null where none.
    const NativeGrid* nativeGridOver(const io::PatchId& id, std::vector<io::PatchId>& out,
                                     LonLatBox& footprint) const;

    std::vector<NativeGrid> m_natives;  // in source order: the finest first
    std::array<io::PatchId, 6> m_roots{};
    /// The horizon's ellipsoid lies inside the ground everywhere: below the deepest terrain.
    double m_occluderShrinkM = 0.0;
};

}  // namespace terrain::runtime
