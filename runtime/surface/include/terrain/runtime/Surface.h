// Surface: the seam between the plane and the globe (DESIGN.md, "The globe"). Everything
// that differs between a planar pyramid and a globe one, and nothing else, is asked of it:
//   - the tiling: the quadtree's roots (one patch, or the six cube faces), each patch's
//     children, which of them the pyramid stores, how deep a patch is split;
//   - a patch's bounding volume V and the tests on it: the distance ρ(c, V) the screen-space
//     error divides by (Yusov & Shevtsov 2011, §5), the view frustum, the horizon;
//   - what a patch without finer data may still show: the globe's curvature;
//   - the camera's conventions (a planar camera in the pyramid's map frame, a globe camera
//     in ECEF with its frame east-north-up where it stands) and where a patch is drawn
//     relative to it (SurfacePlacement.h).
// PlaneSurface and GlobeSurface implement it; the LOD quadtree, the draw, the session and
// the programs are written once over it. Pure, no GL: any thread.
#pragma once

#include "terrain/globe/NativeOffset.h"
#include "terrain/globe/PatchBounds.h"
#include "terrain/pyramid/BlockHeightRanges.h"
#include "terrain/pyramid/NativeTiles.h"
#include "terrain/pyramid/PatchRecord.h"
#include "terrain/pyramid/PyramidLayout.h"
#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/runtime/Aabb.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/HorizonCulling.h"

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string_view>
#include <variant>
#include <vector>

namespace terrain::runtime {

enum class SurfaceKind { Plane, Globe };

/// "planar" or "globe": the `tiling` of the programs' JSON.
std::string_view surfaceName(SurfaceKind kind);

/// A patch's bounding volume V (its footprint between its lowest and highest heights): an
/// axis-aligned box on the plane, an oriented box around the curved patch on the globe. Only
/// the surface that made it measures it.
using PatchVolume = std::variant<Aabb, globe::OrientedBox>;

/// A child of a patch on the surface, and its quadrant: bit (cy · 2 + cx) for the child at
/// offset (cx, cy), as PatchInfo::presentChildren numbers them.
struct SurfaceChild {
    io::PatchId id;
    int quadrant = 0;
};

/// What one frame's camera sees, for the culling tests.
struct SurfaceView {
    glm::dvec3 camera{0.0};
    Frustum frustum;
    /// The horizon (the globe); nothing on the plane, which has none.
    std::optional<EllipsoidalOccluder> horizon;
};

class Surface {
public:
    virtual ~Surface() = default;
    Surface(const Surface&) = delete;
    Surface& operator=(const Surface&) = delete;

    virtual SurfaceKind kind() const = 0;
    const io::PyramidManifest& manifest() const { return m_manifest; }
    const io::PyramidLayout& layout() const { return m_manifest.layout; }

    // The tiling.

    /// The quadtree's roots: the pyramid's root patch; the six cube faces' roots.
    virtual std::span<const io::PatchId> roots() const = 0;
    /// The deepest level the LOD splits to: the pyramid's finest on the plane; on the globe
    /// below its data too, for the ellipsoid's curvature (bare and virtual patches).
    virtual int maxLevel() const = 0;
    /// The children of `id` on the surface, in quadrant order (1 to 4: fewer at a planar
    /// DEM's right and bottom edges); the count.
    virtual int children(const io::PatchId& id, std::array<SurfaceChild, 4>& out) const = 0;
    /// Whether the pyramid stores the child in `quadrant` of a stored patch whose summary is
    /// `parent`: always on the plane; the parent's presentChildren on the globe (sparse).
    virtual bool storesChild(const io::PatchInfo& parent, int quadrant) const = 0;
    /// Whether the pyramid holds finer data under a stored patch: below the finest level on
    /// the plane; some present child on the globe.
    virtual bool hasFinerData(const io::PatchId& id, const io::PatchInfo& info) const = 0;
    /// Whether a patch with no tile (a root not yet resident, or the globe where no data
    /// lies) is drawn as the bare surface: the ellipsoid at height 0 on the globe; never on
    /// the plane, which draws nothing until its root arrives.
    virtual bool drawsBareSurface() const = 0;

    // What a patch's flat triangles miss.

    /// How far the flat triangles of a patch of `level` stray from the surface its samples
    /// stand for (their sag under the ellipsoid, and the sideways offset its slopes turn into
    /// height: `rises` between its neighbouring samples, io::sampleRises; none for a bare
    /// patch): the Err(P) of a bare patch, and what a patch without finer data can still
    /// reduce by splitting (0 on the plane).
    virtual double flatTriangleError(int level, const io::SampleRises& rises) const = 0;
    /// The same for a block simplified by 2^d, d = 1..4 (λ of a patch without a tile).
    virtual std::array<float, 4> flatTriangleBlockErrors(int level,
                                                         const io::SampleRises& rises) const = 0;
    /// The largest distance between two neighbouring samples of `level`, metres.
    virtual double sampleSpacingM(int level) const = 0;

    // Volumes and the tests the LOD makes on them.

    virtual PatchVolume volume(const io::PatchId& id, float minHeight, float maxHeight) const = 0;
    /// ρ(c, V): the distance from `point` to the closest point of V (0 inside).
    virtual double distance(const glm::dvec3& point, const PatchVolume& volume) const = 0;
    /// What `camera` sees: its frustum, and its horizon where the surface has one.
    virtual SurfaceView view(const Camera& camera) const;
    /// Whether V lies entirely outside a plane of the view's frustum (conservative: a volume
    /// near a corner may pass). `planeMask` holds the planes still to test; on the plane the
    /// planes V lies wholly inside are cleared from it for V's children, whose boxes nest in
    /// V (the globe's oriented boxes do not nest, so it tests them all).
    virtual bool outsideFrustum(const SurfaceView& view, const PatchVolume& volume,
                                int& planeMask) const = 0;
    /// Whether V is certainly hidden behind the horizon (never on the plane).
    bool belowHorizon(const SurfaceView& view, const PatchVolume& volume) const;

    // Native leaves (docs/globe.md, "Native leaves"): the globe's finest detail drawn from its
    // sources' own grids, whose finest tiles have ids of their own (io NativeTiles.h). None on
    // the plane, whose finest level is its source's grid.

    /// The native tiles drawn in place of `id`, a data patch without finer data: the finest
    /// tiles of the first native grid (the finest source's) that holds all of the patch and
    /// whose samples are not much further apart than the patch's, appended to `out`; false,
    /// and `out` untouched, where none does.
    virtual bool nativeTilesOver(const io::PatchId& /*id*/,
                                 std::vector<io::PatchId>& /*out*/) const {
        return false;
    }
    /// A native tile's bounding volume between its lowest and highest heights, or that of a
    /// window of it (globe::NativeWindow; {} the whole tile).
    virtual PatchVolume nativeTileVolume(const io::PatchId& tile, float minHeight, float maxHeight,
                                         const globe::NativeWindow& window) const;
    /// How far a native tile's flat triangles, drawn between its samples, can stray along the
    /// normal from the sources' own triangles on the ellipsoid (its sag under a chord, and its
    /// slopes turning the triangles' sideways offset into height): what its Err(P), measured at
    /// the sources' samples, leaves out. `info` is the tile's summary, `rises` its samples'
    /// steepest rises (io::sampleRises). For a window of depth k below the tile, its cells and
    /// rises are the tile's scaled by 2^-k, the sources' triangles interpolated between them.
    struct NativeGeometricErrors {
        double fullM = 0.0;              ///< drawn at full resolution
        std::array<float, 4> blocksM{};  ///< over its blocks simplified by 2^d, d = 1..4
    };
    virtual NativeGeometricErrors nativeGeometricErrors(
        const io::PatchId& /*tile*/, const io::PatchInfo& /*info*/,
        const io::SampleRises& /*rises*/, const globe::NativeWindow& /*window*/) const {
        return {};
    }
    /// Whether over the ground of `id` (a face patch nativeTilesOver answers for) the native
    /// grid it chooses shows its own source's samples alone, on their own triangles: no finer
    /// source, no seam band where it blends into a coarser one. There its tiles' windows can
    /// take the error against the sources down to their flat triangles' (docs/globe.md,
    /// "Native windows"); elsewhere the tile's Err(P), the other sources' miss, stays.
    virtual bool nativeGroundIsPure(const io::PatchId& /*id*/) const { return false; }
    /// Where the ground of `id` (a face patch nativeTilesOver answers for, with a sample
    /// round it) lies on native tile `tile` of those: the box (u min, v min, u max, v max) of
    /// its tile coordinates, unclamped; none for a tile not among them. Only there do the
    /// tile's windows split for it (NativeWindowTree).
    virtual std::optional<glm::dvec4> nativeFootprintOn(const io::PatchId& /*id*/,
                                                        const io::PatchId& /*tile*/) const {
        return std::nullopt;
    }
    /// The same over a window of a native tile (its samples and the cells around them).
    virtual bool nativeWindowIsPure(const io::PatchId& /*tile*/,
                                    const globe::NativeWindow& /*window*/) const {
        return false;
    }
    /// A point of a native tile: the tile and the point's tile coordinates ([0, 1]², sample i
    /// at i / quads).
    struct NativeTilePoint {
        io::PatchId tile;
        double u = 0.0;
        double v = 0.0;
    };
    /// The native tile the LOD would draw under the ellipsoid normal `up` in place of a finest
    /// patch of (layout) level `level` (the first grid, finest first, that holds the point and
    /// whose samples are close enough for that level, as nativeTilesOver chooses), and where
    /// the point lies on it; none where no grid does.
    virtual std::optional<NativeTilePoint> nativeTileUnder(const glm::dvec3& /*up*/,
                                                           int /*level*/) const {
        return std::nullopt;
    }
    /// The geometry of a native tile's grid, for its placement; null for any other id.
    virtual const globe::NativeGridGeometry* nativeGeometry(const io::PatchId& /*tile*/) const {
        return nullptr;
    }

    /// The patch's share of the surface: the shares of patches that tile it add up to
    /// wholeCoverage(), exactly.
    virtual std::uint64_t coverageOf(const io::PatchId& id) const = 0;
    virtual std::uint64_t wholeCoverage() const = 0;

protected:
    explicit Surface(const io::PyramidManifest& manifest) : m_manifest(manifest) {}

private:
    io::PyramidManifest m_manifest;
};

/// The surface of a pyramid: a GlobeSurface for a globe manifest (with its native grids, if
/// any: TileStreamer::nativeGrids), else a PlaneSurface.
std::unique_ptr<Surface> makeSurface(const io::PyramidManifest& manifest,
                                     std::span<const io::NativeGridManifest> nativeGrids = {});

}  // namespace terrain::runtime
