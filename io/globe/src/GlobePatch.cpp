#include "terrain/globe/GlobePatch.h"

#include "terrain/base/Assert.h"
#include "terrain/globe/Wgs84.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace terrain::globe {

namespace {

// One entry per (face, side): the adjacent face, the side of it that touches, and whether the
// coordinate along the edge runs the other way there. Derived from the face frames once, so
// the table cannot disagree with the geometry.
struct FaceEdge {
    int face = 0;
    PatchSide side = PatchSide::Left;
    bool reversed = false;
};

glm::ivec3 outwardAxis(const FaceFrame& frame, PatchSide side) {
    switch (side) {
        case PatchSide::Left:
            return -frame.right;
        case PatchSide::Right:
            return frame.right;
        case PatchSide::Top:
            return -frame.down;
        case PatchSide::Bottom:
            break;
    }
    return frame.down;
}

/// The axis the edge's own coordinate grows along (t for Left/Right, s for Top/Bottom).
glm::ivec3 alongAxis(const FaceFrame& frame, PatchSide side) {
    return side == PatchSide::Left || side == PatchSide::Right ? frame.down : frame.right;
}

constexpr std::array<PatchSide, 4> kSides{PatchSide::Left, PatchSide::Right, PatchSide::Top,
                                          PatchSide::Bottom};

std::array<std::array<FaceEdge, 4>, kCubeFaces> makeFaceEdges() {
    std::array<std::array<FaceEdge, 4>, kCubeFaces> edges{};
    for (int face = 0; face < kCubeFaces; ++face) {
        const FaceFrame& frame = faceFrame(face);
        for (PatchSide side : kSides) {
            FaceEdge& edge = edges[face][static_cast<int>(side)];
            const glm::ivec3 outward = outwardAxis(frame, side);
            for (int other = 0; other < kCubeFaces; ++other) {
                if (faceFrame(other).normal != outward) continue;
                edge.face = other;
                // The shared edge lies on this face's plane: on the other face it is the side
                // whose outward axis is this face's normal.
                for (PatchSide otherSide : kSides) {
                    if (outwardAxis(faceFrame(other), otherSide) == frame.normal)
                        edge.side = otherSide;
                }
                edge.reversed = alongAxis(faceFrame(other), edge.side) != alongAxis(frame, side);
            }
        }
    }
    return edges;
}

const std::array<std::array<FaceEdge, 4>, kCubeFaces>& faceEdges() {
    static const auto edges = makeFaceEdges();
    return edges;
}

// The largest eigenvalue of the symmetric matrix [[a, b], [b, c]]: how far a chord's
// second derivatives bend it along the worst direction.
double largestEigenvalue(double a, double b, double c) {
    return 0.5 * (a + c) + std::sqrt(0.25 * (a - c) * (a - c) + b * b);
}

}  // namespace

PatchNeighbour neighbourOf(const GlobePatchId& id, PatchSide side) {
    const std::int64_t n = patchesPerFaceSide(id.level);
    TERRAIN_ASSERT(id.x >= 0 && id.x < n && id.y >= 0 && id.y < n);
    GlobePatchId inside = id;
    switch (side) {
        case PatchSide::Left:
            inside.x -= 1;
            break;
        case PatchSide::Right:
            inside.x += 1;
            break;
        case PatchSide::Top:
            inside.y -= 1;
            break;
        case PatchSide::Bottom:
            inside.y += 1;
            break;
    }
    constexpr std::array<PatchSide, 4> kOpposite{PatchSide::Right, PatchSide::Left,
                                                 PatchSide::Bottom, PatchSide::Top};
    if (inside.x >= 0 && inside.x < n && inside.y >= 0 && inside.y < n) {
        return {inside, kOpposite[static_cast<int>(side)], false};
    }
    const FaceEdge& edge = faceEdges()[id.face][static_cast<int>(side)];
    const bool vertical = side == PatchSide::Left || side == PatchSide::Right;
    std::int64_t along = vertical ? id.y : id.x;
    if (edge.reversed) along = n - 1 - along;
    GlobePatchId across{edge.face, id.level, 0, 0};
    switch (edge.side) {
        case PatchSide::Left:
            across.x = 0;
            across.y = along;
            break;
        case PatchSide::Right:
            across.x = n - 1;
            across.y = along;
            break;
        case PatchSide::Top:
            across.x = along;
            across.y = 0;
            break;
        case PatchSide::Bottom:
            across.x = along;
            across.y = n - 1;
            break;
    }
    return {across, edge.side, edge.reversed};
}

FacePoint patchSamplePoint(const GlobePatchId& id, int quads, int i, int j) {
    // Integer numerators over a power-of-two denominator: exact in double up to 2^53 samples.
    const double denominator = static_cast<double>(patchesPerFaceSide(id.level)) * quads;
    return {id.face, static_cast<double>(id.x * quads + i) / denominator,
            static_cast<double>(id.y * quads + j) / denominator};
}

FacePoint patchPoint(const GlobePatchId& id, double u, double v) {
    const double size = 1.0 / static_cast<double>(patchesPerFaceSide(id.level));
    return {id.face, (static_cast<double>(id.x) + u) * size,
            (static_cast<double>(id.y) + v) * size};
}

glm::dvec3 patchSampleDirection(const GlobePatchId& id, int quads, int i, int j) {
    const FacePoint p = patchSamplePoint(id, quads, i, j);
    return directionOf(p.face, p.s, p.t);
}

PatchSampleDirections::PatchSampleDirections(const GlobePatchId& id, int quads, int first, int last)
    : m_face(id.face), m_first(first) {
    TERRAIN_ASSERT(first <= last);
    for (int k = first; k <= last; ++k) {
        // patchSamplePoint's s depends on i alone, its t on j alone.
        const FacePoint p = patchSamplePoint(id, quads, k, k);
        m_columns.push_back(cubeCoordinate(p.s));
        m_rows.push_back(cubeCoordinate(p.t));
    }
}

glm::dvec3 PatchSampleDirections::operator()(int i, int j) const {
    return directionOfCubePoint(
        cubePointOfCubeCoordinates(m_face, m_columns[static_cast<std::size_t>(i - m_first)],
                                   m_rows[static_cast<std::size_t>(j - m_first)]));
}

double maxSampleAngle(int level, int quads) {
    return (std::numbers::pi / 2.0) / (static_cast<double>(patchesPerFaceSide(level)) * quads);
}

double maxSampleSpacing(int level, int quads) {
    // An arc of angle θ between normals is at most θ times the largest radius of curvature.
    return maxSampleAngle(level, quads) * Wgs84::kMaxCurvatureRadius;
}

double flatTriangleErrorBound(double sampleSpacing, double minHeight) {
    const double radius = Wgs84::kMinCurvatureRadius + std::min(minHeight, 0.0);
    return 1.001 * sampleSpacing * sampleSpacing / (3.0 * radius);
}

double faceTriangleErrorBound(double sampleAngle, double riseS, double riseT) {
    const double sag = flatTriangleErrorBound(sampleAngle * Wgs84::kMaxCurvatureRadius);
    if (riseS <= 0.0 && riseT <= 0.0) return sag;
    // The tangent adjustment's n″ along the ground, per α² (0.71 at most over a face).
    constexpr double kSideways = 0.75;
    // A cell's shortest side per α·ρ, and the sine of the narrowest angle of its sides.
    constexpr double kShortestSide = 0.7071, kNarrowestSine = 0.8660;
    const double a = sampleAngle, bend = kSideways * Wgs84::kMaxCurvatureRadius * a * a;
    const double hss = 2.0 * riseS * a + bend;
    const double hst = (riseS + riseT) * a + bend;
    const double htt = 2.0 * riseT * a + bend;
    const double largest = largestEigenvalue(hss, hst, htt);
    const double slope =
        (riseS + riseT) / (kShortestSide * a * Wgs84::kMinCurvatureRadius * kNarrowestSine);
    // Σ b_i |d_i|² ≤ ⅔ of a cell side², as for the sag (flatTriangleErrorBound).
    return sag + 1.05 * slope * largest / 3.0;
}

double geographicTriangleErrorBound(const GeographicCells& cells) {
    const double small = Wgs84::kMinCurvatureRadius + std::min(cells.minHeightM, 0.0);
    const double large = Wgs84::kMaxCurvatureRadius + std::max(cells.maxHeightM, 0.0);
    const double south = std::min(cells.southRad, cells.northRad);
    const double north = std::max(cells.southRad, cells.northRad);
    // The latitudes' extremes over [south, north]: |φ| nearest and farthest from the equator.
    const double nearest =
        south <= 0.0 && north >= 0.0 ? 0.0 : std::min(std::abs(south), std::abs(north));
    const double farthest =
        std::min(std::max(std::abs(south), std::abs(north)), 0.5 * std::numbers::pi);
    const double quarter = 0.25 * std::numbers::pi;
    const double sinCos = nearest <= quarter && farthest >= quarter
                              ? 0.5
                              : std::max(std::sin(nearest) * std::cos(nearest),
                                         std::sin(farthest) * std::cos(farthest));
    const double tanFarthest = std::tan(farthest);
    const double a = cells.lonStepRad, b = cells.latStepRad;
    const double east = a * large * std::cos(nearest), northSide = b * large;
    const double rE = cells.riseEastM, rN = cells.riseNorthM;
    const double huu =
        (east * east + 2.0 * rE * rE) / small + (b > 0.0 ? a * a / b : 0.0) * rN * sinCos;
    const double huv = b * rE * tanFarthest + 2.0 * rE * rN / small;
    const double hvv = (northSide * northSide + 2.0 * rN * rN) / small;
    const double largest = largestEigenvalue(huu, huv, hvv);
    const double side = std::max(east, northSide);
    // Σ b_i |d_i|² is at most the triangle's circumradius², ⅔ of a cell side² for the
    // tessellator's triangles (transition strips included), as flatTriangleErrorBound takes.
    return (1.05 + 2.0 * side / small) * largest / 3.0;
}

}  // namespace terrain::globe
