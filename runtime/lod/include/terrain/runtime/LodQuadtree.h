// LodQuadtree: the coarse LOD of Yusov & Shevtsov 2011, §5, as a persistent unbalanced
// patch quadtree updated incrementally every frame (DESIGN.md, "LOD and drawing").
//
// A leaf is split when its screen-space error Err_Scr(P) = γ · Err(P) / ρ(c, V) exceeds
// the coarse threshold ε_c = coarseShare · ε and all its children are resident on the GPU
// (until then the leaf keeps drawing and the children are requested, highest screen-space
// error first); the four (or fewer, at the DEM's edges) leaves under a node are merged back
// when the node's Err_Scr drops below ε_c / hysteresis, so a camera resting near a
// threshold changes nothing from frame to frame.
//
// Frame coherence: ρ(c, V) — the distance from the camera to a box — changes by at most as
// much as the camera moves, so after evaluating a node the tree knows how far the camera
// must travel before the node's decision can change, and schedules the next evaluation on
// an odometer of camera travel. A frame evaluates only the nodes whose distance budget ran
// out (plus the few waiting for children), so the update costs what changed, not the size
// of the tree; a change of γ or ε re-evaluates everything once. Culling walks the tree
// each frame from cached boxes; subtrees that leave the view are collapsed to their root so
// the GPU pool holds the view, not the history of the flight.
//
// Every node of the tree is pinned (TileResidency::pin), so whatever the tree draws stays
// resident without per-frame bookkeeping. The tree sees streaming only through
// TileResidency: no GL, no thread of its own.
#pragma once

#include "terrain/pyramid/PyramidLayout.h"
#include "terrain/runtime/Aabb.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/PatchSelection.h"
#include "terrain/runtime/TerrainGeometry.h"
#include "terrain/runtime/TileResidency.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace terrain::runtime {

/// How a patch's need to split is measured (its "screen error" against the threshold).
enum class SplitRule {
    /// Yusov & Shevtsov 2011, §5: Err_Scr(P) = γ · Err(P) / ρ(c, box).
    ProjectedError,
    /// Livny et al. 2007, Eq. 1: ε = ρ_L · l / d per edge, l the patch's side and d the
    /// camera's distance to the edge, split when some ε > 1. With ρ_L = γ / (R_max · τ)
    /// (R_max = the patch's quads, τ the threshold) that is γ · s / d > τ, s the level's
    /// sample spacing: a full-resolution segment of the nearest edge spans more than τ
    /// pixels. d is measured to the edge extruded over the DEM's height range (the same
    /// for every patch that shares the edge, and no more than the distance to a part of
    /// it, which Livny's Claim 1 needs).
    LivnyEdges,
    /// CDLOD (Strugar 2009): distance ranges doubling level by level. A patch is split while
    /// the camera is nearer its box than R_l = γ · s_l / τ, s_l its level's sample spacing:
    /// where a sample of the level would span more than τ pixels. (γ · s_l / ρ > τ.)
    ProjectedSpacing,
};

struct LodOptions {
    double errorPx = 2.0;  ///< ε, pixels: what the drawn surface (both stages) is held to
    /// The coarse stage selects patches with Err_Scr(P) ≤ coarseShare · ε, leaving the fine
    /// stage room: its bound Λ(d) = λ(d) + Err(P) contains Err(P), so a patch selected at
    /// the whole ε leaves its blocks nothing to simplify, and a larger ε could then draw
    /// more triangles than a smaller one (docs/accuracy.md, "Splitting ε between the
    /// stages").
    double coarseShare = 0.5;
    /// Merge when Err_Scr of the parent < coarse ε / hysteresis (> 1): the band between the
    /// split and the merge thresholds keeps decisions stable.
    double hysteresis = 1.25;
    /// Every leaf in view is split down to the finest level and nothing merges while in
    /// view, whatever its error: the uniform full-resolution grid (LodMethod::Uniform).
    bool splitToFinest = false;
    SplitRule splitRule = SplitRule::ProjectedError;

    /// The coarse stage's threshold, pixels.
    double coarseErrorPx() const { return errorPx * coarseShare; }
};

struct LodUpdateStats {
    std::uint64_t drawn = 0;
    std::uint64_t culled = 0;       ///< leaves outside the frustum
    std::uint64_t evaluations = 0;  ///< split or merge decisions computed this frame
    std::uint64_t splits = 0;
    std::uint64_t merges = 0;         ///< including subtrees collapsed as they left the view
    std::uint64_t waitingSplits = 0;  ///< leaves too coarse whose children are not resident
    std::uint64_t nodes = 0;  ///< nodes in the tree after the update (RTIN: bintree nodes visited)
    std::uint64_t coveredFinestPatches = 0;  ///< as PatchSelectionStats
};

/// Render thread only. Holds pins in `residency`: destroy it before the residency. Allocates
/// nothing per frame once its node and queue storage have grown.
class LodQuadtree {
public:
    LodQuadtree(TileResidency& residency, const TerrainGeometry& geometry, LodOptions options = {});
    ~LodQuadtree();
    LodQuadtree(const LodQuadtree&) = delete;
    LodQuadtree& operator=(const LodQuadtree&) = delete;

    /// Updates the tree for `camera` (inside the residency's frame, e.g. between
    /// TileStreamer::beginFrame and endFrame) and
    /// fills `out` with the visible leaves (cleared first). Empty until the root arrives.
    LodUpdateStats update(const Camera& camera, std::vector<PatchDraw>& out);

    void setOptions(const LodOptions& options);
    const LodOptions& options() const { return m_options; }

    /// The first broken invariant, or nullopt: leaves tile the domain exactly once,
    /// children exist only as complete sets (every contained child), every node is pinned
    /// and resident on the layer it records, parent links agree. O(nodes): for tests.
    std::optional<std::string> checkInvariants() const;

private:
    enum class CheckKind : std::uint8_t { Split, Merge };
    struct Node {
        io::PatchId id;
        Aabb box;
        float errorM = 0.0f;
        int layer = -1;
        int parent = -1;
        int firstChild = -1;  // childCount consecutive nodes
        std::uint8_t childCount = 0;
        bool visible = false;
        bool waiting = false;          // in m_waiting
        bool splitBlocked = false;     // a child failed to load: never splits
        std::uint32_t generation = 0;  // bumped when a node changes: stale checks are skipped
        bool leaf() const { return childCount == 0; }
    };
    struct Check {
        double atOdometer;
        int node;
        std::uint32_t generation;
        CheckKind kind;
    };

    double screenError(const Node& node) const;
    /// The metres the split rule projects: Err(P), or the level's sample spacing (Livny).
    double metricM(const Node& node) const;
    /// The distance the split rule divides by: to the box, or to the nearest edge (Livny).
    double decisionDistance(const Node& node) const;
    void schedule(int node, CheckKind kind, double travel);
    void pushCheck(int node, CheckKind kind, double atOdometer);
    void scheduleLeaf(int node);
    void scheduleMergeIfCandidate(int node);
    bool trySplit(int node, double screenError);
    void evaluateLeaf(int node);
    void evaluateMerge(int node);
    void collapse(int node);
    int allocateBlock();
    void freeBlock(int first);
    void cull(int node, int planeMask, std::vector<PatchDraw>& out);

    TileResidency& m_residency;
    const TerrainGeometry& m_geometry;
    LodOptions m_options;

    std::vector<Node> m_nodes;  // blocks of 4; the root is node 0 (alone in block 0)
    std::vector<int> m_freeBlocks;
    std::vector<Check> m_checks;  // min-heap on atOdometer
    std::vector<int> m_waiting;   // leaves re-tried every frame
    std::vector<int> m_waitingNext;

    Camera m_camera;
    Frustum m_frustum;
    double m_gamma = 0.0;
    double m_odometer = 0.0;
    bool m_haveRoot = false;
    bool m_recheckAll = true;
    LodUpdateStats m_stats;
};

}  // namespace terrain::runtime
