// GlobePatch: the patch quadtree of each cube face (DESIGN.md, "The globe"). Level l holds
// 2^l × 2^l patches a face; a patch of `quads` quads a side (N = quads + 1 samples) has its
// samples at face coordinates s = (x·quads + i) / (2^l·quads), t likewise, so a sample on a
// patch edge is the same dyadic face point for both patches that share it, and one on a cube
// edge is the same cube point from both faces (CubeSphere.h). Across a cube edge the neighbour
// is on another face whose axes are rotated: neighbourOf says which patch, which of its
// sides, and whether the shared edge runs the other way there.
#pragma once

#include "terrain/globe/CubeSphere.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace terrain::globe {

struct GlobePatchId {
    int face = 0;
    int level = 0;
    std::int64_t x = 0;  ///< column of patches along the face's s
    std::int64_t y = 0;  ///< row along t
    bool operator==(const GlobePatchId&) const = default;
};

/// A patch side in face terms: Left is s = min, Right s = max, Top t = min, Bottom t = max.
enum class PatchSide : int { Left = 0, Right, Top, Bottom };

struct PatchNeighbour {
    GlobePatchId id;
    PatchSide side;  ///< the side of `id` that touches the asking patch
    /// True when the shared edge's sample k of the asking patch is sample N − 1 − k of the
    /// neighbour (only across some cube edges).
    bool reversed = false;
};

inline std::int64_t patchesPerFaceSide(int level) { return std::int64_t{1} << level; }

/// The patch across `side` (on this face or, at a face edge, on the adjacent face).
PatchNeighbour neighbourOf(const GlobePatchId& id, PatchSide side);

/// Face coordinates of the patch's sample (i, j); i, j = −1 and quads + 1 are the apron.
FacePoint patchSamplePoint(const GlobePatchId& id, int quads, int i, int j);
/// Face coordinates of a fractional position (u, v) in [0, 1]² of the patch.
FacePoint patchPoint(const GlobePatchId& id, double u, double v);
/// The unit direction (ellipsoid normal) of the patch's sample (i, j).
glm::dvec3 patchSampleDirection(const GlobePatchId& id, int quads, int i, int j);

/// patchSampleDirection for every sample (i, j) of a patch with first ≤ i, j ≤ last, bit
/// for bit, with each column's and each row's cube coordinate (a tangent) computed once
/// rather than at every sample: what the builders' loops over a patch's samples use.
class PatchSampleDirections {
public:
    PatchSampleDirections(const GlobePatchId& id, int quads, int first, int last);

    glm::dvec3 operator()(int i, int j) const;

private:
    int m_face = 0, m_first = 0;
    std::vector<double> m_columns, m_rows;  // cubeCoordinate of s, of t
};

/// The largest angle, in radians, between two neighbouring samples of a level (along s or t):
/// π/2 / (2^l · quads), since the tangent adjustment's dd/ds never exceeds π/2 over a face.
double maxSampleAngle(int level, int quads);
/// The largest distance between two neighbouring samples at height 0, metres.
double maxSampleSpacing(int level, int quads);
/// How far the ellipsoid (or a surface at height ≥ minHeight along its normal) can stray from
/// the flat triangles of a sample grid whose sides are at most `sampleSpacing`: a triangle
/// with two such sides fits in a circle of radius r ≤ √(2/3)·spacing, and a surface whose radii
/// of curvature are at least ρ = ρ_min + min(minHeight, 0) rises at most ≈ r²/(2ρ) over it,
/// so spacing²/(3ρ) (with 0.1 % to spare for the approximation). This is the part of a globe
/// patch's Err(P) that the planar builder never had.
double flatTriangleErrorBound(double sampleSpacing, double minHeight = 0.0);

/// flatTriangleErrorBound for cells of a cube face whose samples are `sampleAngle` apart at
/// most (maxSampleAngle, times 2^k for a block simplified by 2^k, halved for each level a
/// virtual patch lies below its tile), plus what their slopes add: the largest |height
/// difference| between neighbouring samples along s (`riseS`) and t (`riseT`), metres. A flat
/// triangle lies sideways of the points of the same face coordinates (its corners' normals
/// diverge, the sides of a rising cell with them, 2·h′·n′; and the tangent adjustment spaces a
/// face line's points unevenly, n″ along the ground up to 0.71·α²), and a slope turns that into
/// height. Per cell: the sideways second derivatives are at most 2·r_s·α + c·ρ·α² (s, s),
/// (r_s + r_t)·α + c·ρ·α² (s, t) and 2·r_t·α + c·ρ·α² (t, t), c = 0.75; the chord strays
/// sideways by at most a third of their largest eigenvalue (Σ b_i |d_i|² ≤ ⅔, as for the
/// sag), and the slope is at most (r_s + r_t)/(0.707·α·ρ_min·sin 60°) (a
/// cell's sides are at least 0.707·α·ρ and meet at 60° or more). FaceCellErrorTest checks it
/// against the ellipsoid by brute force; with no rise it is flatTriangleErrorBound.
double faceTriangleErrorBound(double sampleAngle, double riseS, double riseT);

/// Cells of a longitude/latitude grid (a native tile's, or its blocks simplified by 2^d):
/// their angular size, the latitudes they span and their steepest rise between neighbouring
/// samples, and the heights they hold.
struct GeographicCells {
    double lonStepRad = 0.0;  ///< Δλ of one cell
    double latStepRad = 0.0;  ///< Δφ of one cell
    double southRad = 0.0;    ///< the southernmost latitude the cells reach
    double northRad = 0.0;    ///< the northernmost
    double riseEastM = 0.0;   ///< largest |height difference| between a sample and its east one
    double riseNorthM = 0.0;  ///< largest |height difference| between a sample and its north one
    double minHeightM = 0.0;
    double maxHeightM = 0.0;
};

/// How far the flat triangles drawn between a longitude/latitude grid's samples (each cell
/// split NW–SE, as the source's own triangles) can stray, along the ellipsoid normal, from
/// those triangles lifted onto the ellipsoid: the height a point of a drawn triangle has, against
/// the source's height at the point's own latitude and longitude (what GlobeTruth measures).
///
/// flatTriangleErrorBound counts only the ellipsoid's sag under a chord. A flat triangle also
/// strays sideways from the parameter-linear points, and a slope turns that into height: the
/// sides of a rising cell diverge with the normals (2·h′·n′), and lines of latitude are not
/// great circles (n_λλ has a poleward part sinφ·cosφ, n_λφ an eastward sinφ). Of F(u, v) =
/// P(φ, λ) + h·n over a cell's parameters (u east, v south, one cell = 1), the height error of
/// the chord is ½·Σ b_i d_iᵀ H d_i ≤ λ_max(|H|)/3 (barycentric b_i, offsets d_i to the
/// vertices: Σ b_i |d_i|² is at most the triangle's circumradius², which flatTriangleErrorBound
/// takes as ⅔ of a cell side² for every triangle the tessellator draws, transition strips
/// included; ½ for the grid's own right triangles), where H bounds the normal
/// part of F's second derivatives plus the tangential part times the slope:
///   H_uu = e²/ρ + 2·r_E²/ρ + (Δλ²/Δφ)·r_N·|sinφ cosφ|,
///   H_uv = Δφ·r_E·|tanφ| + 2·r_E·r_N/ρ,
///   H_vv = n²/ρ + 2·r_N²/ρ,
/// with e, n the cells' east and north sides (at the largest radius), r_E, r_N the rises and
/// ρ the smallest radius of curvature less any depth below the ellipsoid. With 5 % to spare,
/// plus 2·side/ρ for the third-order terms of cells as large as a simplified 20′ block.
/// GeographicCellErrorTest checks it against the ellipsoid by brute force, from the equator to
/// 89.7°. With no slope it is about flatTriangleErrorBound; at a rise of one cell side, or
/// near a pole, it is several times larger.
double geographicTriangleErrorBound(const GeographicCells& cells);

}  // namespace terrain::globe
