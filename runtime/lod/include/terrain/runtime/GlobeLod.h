// GlobeLod: the coarse LOD on the globe (DESIGN.md, "The globe", LOD), selected from the six
// cube-face roots every frame. A patch is split when its screen-space error
//     γ · Err(P) / ρ(c, V)
// exceeds ε (Yusov & Shevtsov 2011, §5), with ρ the distance to the patch's true bounding
// volume on the ellipsoid (globe::patchBounds, heights included, metres everywhere), so the
// same view needs about the same patches at a pole, on the equator and at a cube corner.
// Patches outside the view frustum or behind the horizon (EllipsoidalOccluder) are culled.
//
// A globe pyramid is sparse. Where it holds no patch the LOD draws the bare ellipsoid
// (height 0): a bare patch's Err(P) is how far its flat triangles fall under the ellipsoid
// (globe::flatTriangleErrorBound), so bare patches refine with distance too, from no data at
// all. A data patch splits only when every present child (its presentChildren mask) is
// resident. An absent child is virtual: it draws its parent's tile over its quadrant
// (interpolated), as do its own children; a virtual patch splits only for the ellipsoid's
// curvature (the data's error cannot shrink without finer data). A face root that has not
// arrived yet is drawn bare.
//
// Hysteresis, as in LodQuadtree: a patch split last frame stays split until its screen-space
// error drops below ε / hysteresis, so a camera resting near a threshold changes nothing from
// frame to frame (splitting more only lowers the error). Between frames the LOD keeps, per
// patch it visited, only its box and the last frame that split it: it still visits every
// patch it keeps or splits each frame (tens of patches, 12 µs median on the Rainier flight,
// docs/globe.md), so LodQuadtree's scheduling of evaluations by camera travel would save
// nothing measurable here.
#pragma once

#include "terrain/globe/GlobePatch.h"
#include "terrain/globe/PatchBounds.h"
#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/HorizonCulling.h"
#include "terrain/runtime/TileResidency.h"

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace terrain::runtime {

struct GlobePatchDraw {
    globe::GlobePatchId id;
    int layer = -1;       ///< the GPU pool layer, or −1: the bare ellipsoid (height 0)
    float errorM = 0.0f;  ///< Err(P)
    float skirtDepthM = 0.0f;
    float minHeight = 0.0f;
    float maxHeight = 0.0f;
    /// λ(1..4) of a patch without a tile of its own (bare or virtual): how far the ellipsoid
    /// bulges over its blocks simplified by 2^d (plus, for a virtual one, its tile's λ).
    std::array<float, 4> bareBlockErrorsM{};
    /// A virtual patch has no tile of its own (an absent child of a data patch, or a child of
    /// one): it draws `layer`, the tile of its ancestor `tileId`, whose sample
    /// texelOffset + s · texelStep lies under its sample s. A data patch: its own tile, 0, 1.
    bool isVirtual = false;
    globe::GlobePatchId tileId;
    std::array<float, 2> texelOffset{0.0f, 0.0f};
    float texelStep = 1.0f;
};

struct GlobeLodOptions {
    double errorPx = 2.0;  ///< ε, pixels
    bool frustumCulling = true;
    bool horizonCulling = true;
    /// The finest level bare patches refine to (a 129-sample patch there is ~15 cm wide).
    int maxBareLevel = 24;
    /// A patch split last frame is merged when its screen-space error < ε / hysteresis
    /// (≥ 1; 1: no hysteresis, every frame decided afresh).
    double hysteresis = 1.25;
};

struct GlobeLodStats {
    std::uint64_t drawn = 0;
    std::uint64_t drawnBare = 0;
    std::uint64_t drawnVirtual = 0;
    std::uint64_t frustumCulled = 0;
    std::uint64_t horizonCulled = 0;
    std::uint64_t visited = 0;
    std::uint64_t waitingSplits = 0;  ///< drawn although too coarse: children not resident
    /// Split although within ε: split last frame and still above ε / hysteresis.
    std::uint64_t heldSplits = 0;
    int deepestLevel = 0;
    /// The area the drawn and culled patches cover, a patch of level l counting 4^(30 − l):
    /// kWholeGlobeCoverage exactly when they tile the six faces with no hole and no overlap.
    std::uint64_t coverage = 0;
    static constexpr int kCoverageLevels = 30;
    static constexpr std::uint64_t kWholeGlobeCoverage = std::uint64_t{6} << (2 * kCoverageLevels);
};

/// Render thread only.
class GlobeLod {
public:
    /// `manifest` must be a globe pyramid's (manifest.globe set).
    GlobeLod(const io::PyramidManifest& manifest, TileResidency& residency,
             const GlobeLodOptions& options = {});

    /// Fills `out` (cleared) with the patches to draw for `camera` (ECEF position, its frame
    /// east-north-up: GlobeCamera.h), requesting the data patches it wants.
    GlobeLodStats select(const Camera& camera, std::vector<GlobePatchDraw>& out);

    const GlobeLodOptions& options() const { return m_options; }
    void setOptions(const GlobeLodOptions& options);

    /// Err(P) of a bare patch of `level`: the sag of its flat triangles under the ellipsoid.
    double bareError(int level) const;

private:
    struct Node {
        globe::GlobePatchId id;
        const io::PatchInfo* info = nullptr;  // the tile's summary: null for a bare patch
        // A virtual patch draws its ancestor's tile (`info` is the ancestor's).
        bool isVirtual = false;
        globe::GlobePatchId tileId;
        double texelOffsetX = 0.0, texelOffsetY = 0.0, texelStep = 1.0;
    };
    void visit(const Node& node, GlobeLodStats& stats, std::vector<GlobePatchDraw>& out);
    struct PatchState;
    PatchState& stateOf(const globe::GlobePatchId& id, float minHeight, float maxHeight);
    GlobePatchDraw drawOf(const Node& node) const;

    TileResidency& m_residency;
    GlobeLodOptions m_options;
    int m_quads = 0;
    double m_occluderShrink = 0.0;
    EllipsoidalOccluder m_occluder;
    // Per-frame state of select().
    glm::dvec3 m_camera{0.0};
    double m_gamma = 1.0;
    Frustum m_frustum;
    // What the LOD keeps of a patch it visited: its box, for the heights it was made for,
    // and the last frame that split it (the hysteresis).
    struct PatchState {
        globe::OrientedBox box;
        float minHeight = 0.0f;
        float maxHeight = 0.0f;
        std::uint64_t splitInFrame = 0;  // 0: never
    };
    std::unordered_map<std::uint64_t, PatchState> m_patches;  // by patchKey
    std::uint64_t m_frame = 0;                                // select() calls so far
};

}  // namespace terrain::runtime
