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

}  // namespace terrain::globe
