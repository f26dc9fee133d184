// LodQuadtree: the coarse LOD of Yusov & Shevtsov 2011, §5, as a persistent unbalanced
// patch quadtree updated incrementally every frame (DESIGN.md, "LOD and drawing"), on the
// plane and on the globe alike: the Surface (Surface.h) says where patches lie, and the
// tree is one.
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
// A globe pyramid is sparse (DESIGN.md, "The globe"): where it holds no patch the tree draws
// the bare ellipsoid (height 0), whose Err(P) is how far its flat triangles fall under the
// ellipsoid (Surface::flatTriangleError), so bare patches refine with distance too. A child the
// pyramid does not store under a data patch is virtual: it draws its parent's tile over its
// quadrant (interpolated), as do its own children, and splits for the curvature alone (the
// data's error cannot shrink without finer data). A root not yet resident is drawn bare
// (the plane draws nothing until its root arrives). Patches behind the horizon are culled
// like those outside the frustum. On the plane every patch is a data patch.
//
// Every node that draws its own tile is pinned (TileResidency::pin), so whatever the tree
// draws stays resident without per-frame bookkeeping (a virtual node's tile is its pinned
// ancestor's). The tree sees streaming only through TileResidency: no GL, no thread of its
// own.
#pragma once

#include "terrain/pyramid/PyramidLayout.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/NativeWindowTree.h"
#include "terrain/runtime/PatchDraw.h"
#include "terrain/runtime/Surface.h"
#include "terrain/runtime/TileResidency.h"

#include <cstdint>
#include <optional>
#include <string>
#include <unordered_map>
#include <utility>
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
    /// The coarse stage selects patches with Err_Scr(P) ≤ coarseShare · ε. Unset: the
    /// surface's own (defaultCoarseShare). On the plane half, leaving the fine stage room:
    /// its bound Λ(d) = λ(d) + Err(P) contains Err(P), so a patch selected at the whole ε
    /// leaves its blocks nothing to simplify, and a larger ε could then draw more triangles
    /// than a smaller one (docs/accuracy.md, "Splitting ε between the stages").
    std::optional<double> coarseShare{};
    /// Merge when Err_Scr of the parent < coarse ε / hysteresis (> 1): the band between the
    /// split and the merge thresholds keeps decisions stable.
    double hysteresis = 1.25;
    /// Every leaf in view is split down to the finest level and nothing merges while in
    /// view, whatever its error: the uniform full-resolution grid (LodMethod::Uniform).
    bool splitToFinest = false;
    SplitRule splitRule = SplitRule::ProjectedError;
    /// Cull patches hidden behind the horizon (the globe; the plane has none). False for
    /// comparisons.
    bool horizonCulling = true;
    /// The most pixels one of a drawn patch's samples may span (the projected rule:
    /// γ · s_l / ρ ≤ maxSamplePx, s_l the level's sample spacing), where finer data would
    /// shade differently (Err(P) > s_l · kShadingSlopeTolerance); 0: no limit, the geometric
    /// bound alone (Yusov's rule; the sessions' default is 1, TerrainSessionOptions). The
    /// shading (normals, tint, the sea's coast, a source's edge) comes from the drawn patch's
    /// samples, so a patch whose samples span several pixels shades coarser than the data,
    /// and differently from a finer neighbour: the geometric bound alone lets a smooth patch
    /// stay coarse long after its detail would show (a Rainier tile seen from 300 km drew
    /// blurred, 35.4 dB against 41.8 dB with this rule). With it a pixel's shading data is as
    /// fine as the pixel, whichever level draws it; finer than a pixel it is filtered to the
    /// pixel's footprint (shaders/terrain_footprint.glsl).
    double maxSamplePx = 0.0;
    /// Reading ahead along the camera's motion: a drawn leaf whose projected error from where
    /// the camera will be this many frames on, at its present velocity, exceeds the coarse
    /// threshold has its children read ahead (TileResidency::prefetch; a finest globe patch,
    /// the native tiles it would split into). About the frames a
    /// tile takes from request to residency from a local disk; further ahead costs reads the
    /// camera may never need. 0: off (the reading ahead below waiting leaves stays).
    double readAheadFrames = 8.0;
    /// A patch within Err(P) of the finer data tilts no normal by more than about
    /// 2 · Err(P) / s_l radians: below 1/255 (a Lambertian brightness change under one 8-bit
    /// level) splitting it changes nothing a viewer sees, and a flat patch is never split.
    static constexpr double kShadingSlopeTolerance = 1.0 / 510.0;

    /// The coarse stage's share of ε on `surface` when coarseShare is unset.
    static double defaultCoarseShare(SurfaceKind surface);
    /// The coarse stage's threshold, pixels.
    double coarseErrorPx(SurfaceKind surface) const {
        return errorPx * coarseShare.value_or(defaultCoarseShare(surface));
    }
};

struct LodUpdateStats {
    std::uint64_t drawn = 0;
    std::uint64_t drawnBare = 0;      ///< of them, bare patches (no tile: the globe's ellipsoid)
    std::uint64_t drawnVirtual = 0;   ///< of them, virtual patches (an ancestor's tile)
    /// Of them, native draws: tiles of a source's own grid (docs/globe.md, "Native leaves"),
    /// whole or as windows.
    std::uint64_t drawnNative = 0;
    /// Of those, windows below a whole tile (NativeWindowTree), and the deepest one's depth.
    std::uint64_t drawnNativeWindows = 0;
    int deepestNativeWindow = 0;
    std::uint64_t culled = 0;         ///< leaves outside the frustum
    std::uint64_t horizonCulled = 0;  ///< leaves behind the horizon (the globe)
    std::uint64_t visited = 0;        ///< nodes the culling walk visited
    std::uint64_t evaluations = 0;    ///< split or merge decisions computed this frame
    std::uint64_t splits = 0;
    std::uint64_t merges = 0;         ///< including subtrees collapsed as they left the view
    std::uint64_t waitingSplits = 0;  ///< leaves too coarse whose children are not resident
    /// Of them, finest globe patches whose native tiles are not resident.
    std::uint64_t waitingNativeSplits = 0;
    /// Tiles asked for ahead (TileResidency::prefetch) this frame: below waiting leaves, and
    /// the children of drawn leaves the camera's motion will likely split.
    std::uint64_t prefetched = 0;
    /// Visible nodes held split although within the coarse threshold (the hysteresis).
    std::uint64_t heldSplits = 0;
    std::uint64_t nodes = 0;  ///< nodes in the tree after the update (RTIN: bintree nodes visited)
    int deepestLevel = 0;     ///< the deepest drawn patch's (layout) level
    /// The drawn and culled patches' shares of the surface (Surface::coverageOf): the
    /// surface's wholeCoverage() exactly when they tile it with no hole and no overlap (and
    /// something was drawn).
    std::uint64_t coverage = 0;
};

/// Render thread only. Holds pins in `residency`: destroy it before the residency. Allocates
/// nothing per frame once its node and queue storage have grown.
class LodQuadtree {
public:
    LodQuadtree(TileResidency& residency, const Surface& surface, LodOptions options = {});
    ~LodQuadtree();
    LodQuadtree(const LodQuadtree&) = delete;
    LodQuadtree& operator=(const LodQuadtree&) = delete;

    /// Updates the tree for `camera` (inside the residency's frame, e.g. between
    /// TileStreamer::beginFrame and endFrame) and
    /// fills `out` with the visible leaves (cleared first). Empty until the root arrives.
    LodUpdateStats update(const Camera& camera, std::vector<PatchDraw>& out);

    void setOptions(const LodOptions& options);
    const LodOptions& options() const { return m_options; }

    /// The first broken invariant, or nullopt: leaves tile the surface exactly once,
    /// children exist only as complete sets (every child on the surface), every node that
    /// draws its own tile is pinned and resident on the layer it records (a virtual one's
    /// tile is resident on it), parent links agree. O(nodes): for tests.
    std::optional<std::string> checkInvariants() const;

private:
    enum class CheckKind : std::uint8_t { Split, Merge };
    enum class NodeKind : std::uint8_t {
        Data,     ///< draws its own tile
        Virtual,  ///< draws a quadrant of an ancestor's tile (the globe)
        Bare,     ///< no tile: the bare surface (the globe's ellipsoid)
        /// The only child of a data patch without finer data: draws the native tiles over its
        /// parent (Surface::nativeTilesOver; docs/globe.md, "Native leaves"), and never splits
        /// in this tree: its tiles split into windows of their own (NativeWindowTree).
        Native,
    };
    struct Node {
        io::PatchId id;
        PatchVolume volume;
        io::PatchInfo info;   // a data node's summary; a virtual node's tile's
        float errorM = 0.0f;  // Err(P) as drawn
        double splitM = 0.0;  // what a split can reduce: Err(P) above finer data, else curvature
        int layer = -1;       // the drawn tile's layer; −1: bare
        io::PatchId tile;     // the drawn tile: `id`, or a virtual node's ancestor
        double texelOffsetX = 0.0, texelOffsetY = 0.0, texelStep = 1.0;
        // Its samples' steepest rises (its tile's, halved for each level a virtual patch lies
        // below it; none for a bare patch): what its flat triangles' slope terms need.
        io::SampleRises rises{};
        int parent = -1;
        int firstChild = -1;  // childCount consecutive nodes
        std::uint8_t childCount = 0;
        NodeKind kind = NodeKind::Data;
        bool finerData = false;     // a data node with finer data under it
        bool nativeCapable = false;  // a data node without finer data that native tiles cover
        bool awaitingTile = false;  // a bare root whose tile is on its way (the globe)
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
    /// The metres the split rule projects: what a split reduces, or the level's sample
    /// spacing (Livny, CDLOD).
    double metricM(const Node& node) const;
    /// The distance the split rule divides by: to the volume, or to the nearest edge (Livny).
    double decisionDistance(const Node& node) const;
    double coarseErrorPx() const { return m_options.coarseErrorPx(m_surface.kind()); }
    bool start();
    void makeDataNode(Node& node, const io::PatchId& id, const io::PatchInfo& info);
    void makeChild(Node& child, const Node& parent, const SurfaceChild& at,
                   const io::PatchInfo* info);
    void takeArrivedRoots();
    PatchDraw drawOf(const Node& node) const;
    void schedule(int node, CheckKind kind, double travel);
    void pushCheck(int node, CheckKind kind, double atOdometer);
    void scheduleLeaf(int node);
    void scheduleMergeIfCandidate(int node);
    bool trySplit(int node, double screenError);
    /// A split into the native tiles over the node (NodeKind::Native): 1 made, −1 waiting for
    /// the tiles, 0 not worth it (their own error shows as much as the node's).
    int trySplitNative(int node, double screenError);
    void pinNative(const io::PatchId& tile);
    void unpinNative(const io::PatchId& tile);
    void emitNative(int node, std::vector<PatchDraw>& out);
    /// The steepest rises of a resident tile's samples (TileResidency::residentSampleRises).
    io::SampleRises residentRises(const io::PatchId& id) const;
    /// Whether native tiles split into windows (NativeWindowTree): under the projected-error
    /// rule, not for the uniform grid.
    bool refinesNativeWindows() const;
    /// After the frame's draws are listed: each native tile's ground (NativeOwnership.h).
    void assignNativeOwnerships(std::vector<PatchDraw>& out);
    void prefetchBelow(const io::PatchId& id, const io::PatchInfo& heights, double errorM,
                       double decay, int levels, const io::PatchInfo* stored);
    double errorDecay(const Node& node) const;
    void prefetchUnderRoot(const io::PatchId& root);
    void prefetchAlongMotion(const Node& leaf);
    float prefetchPriority(double predicted) const;
    void evaluateLeaf(int node);
    void evaluateMerge(int node);
    void collapse(int node);
    int allocateBlock();
    void freeBlock(int first);
    void cull(int node, int planeMask, std::vector<PatchDraw>& out);

    TileResidency& m_residency;
    const Surface& m_surface;
    LodOptions m_options;

    // Blocks of 4 nodes; the roots first, in the blocks they fill (spare slots unused).
    std::vector<Node> m_nodes;
    int m_rootCount = 0;
    int m_rootSlots = 0;  // the root blocks' slots
    std::vector<int> m_freeBlocks;
    std::vector<Check> m_checks;  // min-heap on atOdometer
    std::vector<int> m_waiting;   // leaves re-tried every frame
    std::vector<int> m_waitingNext;
    // Native tiles: the pins the native nodes hold (a tile may lie under several) with each
    // pinned tile's windows, the tiles drawn this frame (each once, as a run of draws), and
    // scratch lists.
    struct NativePin {
        io::PatchId tile;
        int holders = 0;
        int windows = -1;  // its NativeWindowTree root
    };
    struct NativeDrawn {
        io::PatchId tile;
        std::size_t first = 0;  // its draws in the frame's list
        std::size_t count = 0;
    };
    std::vector<NativePin> m_nativePins;
    std::unordered_map<int, std::vector<io::PatchId>> m_nativeTiles;  // by native node
    // The native node's ground on each of its tiles (Surface::nativeFootprintOn), as listed.
    std::unordered_map<int, std::vector<glm::dvec4>> m_nativeFootprints;
    std::vector<NativeDrawn> m_nativeDrawn;
    NativeWindowTree m_windows;
    std::vector<io::PatchId> m_holderScratch;
    std::vector<io::PatchId> m_nativeScratch;

    Camera m_camera;
    glm::dvec3 m_motion{0.0};  // the camera's move since the last update
    SurfaceView m_view;
    double m_gamma = 0.0;
    double m_odometer = 0.0;
    bool m_started = false;
    bool m_recheckAll = true;
    LodUpdateStats m_stats;
};

}  // namespace terrain::runtime
