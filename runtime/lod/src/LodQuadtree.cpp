// LodQuadtree: nodes in blocks of four, a min-heap of checks keyed on camera travel, a list
// of leaves waiting for their children, and a culling walk that emits the draw list.
#include "terrain/runtime/LodQuadtree.h"

#include "terrain/base/Assert.h"
#include "terrain/pyramid/PatchErrors.h"
#include "terrain/runtime/NativeOwnership.h"
#include "terrain/runtime/PlaneSurface.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace terrain::runtime {
namespace {

constexpr int kBlock = 4;
constexpr double kMinTravelM = 1e-3;
// Levels below a waiting leaf's children that prefetchBelow may ask for ahead.
constexpr int kPrefetchLevels = 3;
// The smallest decay of Err(P) a level that prefetchBelow predicts: smooth terrain's.
constexpr double kHalving = 0.5;
// Parent links: −1 a root, −2 a freed node, −3 a spare slot of the root blocks.
constexpr int kFreed = -2;
constexpr int kSpare = -3;

bool laterCheck(const auto& a, const auto& b) { return a.atOdometer > b.atOdometer; }

float priorityOf(double screenError) {
    return static_cast<float>(std::min(screenError, double{std::numeric_limits<float>::max()}));
}

void checkOptions(const LodOptions& options) {
    const double share = options.coarseShare.value_or(0.5);
    TERRAIN_ASSERT(options.errorPx > 0.0 && share > 0.0 && share <= 1.0 &&
                       options.hysteresis >= 1.0 && options.readAheadFrames >= 0.0,
                   "LodQuadtree: bad options");
}

}  // namespace

double LodOptions::defaultCoarseShare(SurfaceKind surface) {
    // The globe's draw holds only what the simplification adds, λ(d), to ε where Err(P) alone
    // shows more than ε (shaders/terrain.tesc), and its figures were made splitting at the
    // whole ε (docs/globe.md).
    return surface == SurfaceKind::Globe ? 1.0 : 0.5;
}

LodQuadtree::LodQuadtree(TileResidency& residency, const Surface& surface, LodOptions options)
    : m_residency(residency), m_surface(surface), m_options(options), m_windows(surface) {
    checkOptions(options);
    TERRAIN_ASSERT(
        options.splitRule != SplitRule::LivnyEdges || surface.kind() == SurfaceKind::Plane,
        "LodQuadtree: Livny's edges are planar");
    m_rootCount = static_cast<int>(surface.roots().size());
    m_rootSlots = (m_rootCount + kBlock - 1) / kBlock * kBlock;
    const auto capacity = static_cast<std::size_t>(residency.capacity());
    m_nodes.reserve(kBlock * (capacity + 1) + static_cast<std::size_t>(m_rootSlots));
    m_freeBlocks.reserve(capacity + 1);
    m_checks.reserve(4 * capacity + 16);
    m_waiting.reserve(capacity + 1);
    m_waitingNext.reserve(capacity + 1);
}

LodQuadtree::~LodQuadtree() {
    if (!m_started) return;
    for (int root = 0; root < m_rootCount; ++root) {
        collapse(root);
        const Node& node = m_nodes[static_cast<std::size_t>(root)];
        if (node.kind == NodeKind::Data) m_residency.unpin(node.id);
    }
}

void LodQuadtree::setOptions(const LodOptions& options) {
    checkOptions(options);
    m_options = options;
    m_recheckAll = true;
}

int LodQuadtree::allocateBlock() {
    if (!m_freeBlocks.empty()) {
        const int first = m_freeBlocks.back();
        m_freeBlocks.pop_back();
        return first;
    }
    const int first = static_cast<int>(m_nodes.size());
    m_nodes.resize(m_nodes.size() + kBlock);
    for (int i = 0; i < kBlock; ++i) m_nodes[static_cast<std::size_t>(first + i)].parent = kFreed;
    return first;
}

void LodQuadtree::freeBlock(int first) { m_freeBlocks.push_back(first); }

// Err_Scr(P) = γ · Err(P) / ρ(c, V) (Yusov & Shevtsov 2011, §5); infinite inside V unless
// the patch is exact.
double LodQuadtree::screenError(const Node& node) const {
    const double metric = metricM(node);
    if (metric <= 0.0) return 0.0;
    const double rho = decisionDistance(node);
    if (rho <= 0.0) return std::numeric_limits<double>::infinity();
    return m_gamma * metric / rho;
}

double LodQuadtree::metricM(const Node& node) const {
    if (m_options.splitRule != SplitRule::ProjectedError)
        return m_surface.sampleSpacingM(node.id.level);
    const double error = static_cast<double>(node.splitM);
    if (m_options.maxSamplePx <= 0.0 || !node.finerData) return error;
    const double spacing = m_surface.sampleSpacingM(node.id.level);
    if (error <= spacing * LodOptions::kShadingSlopeTolerance) return error;
    // γ · s / ρ > maxSamplePx  ⇔  γ · (s · ε_c / maxSamplePx) / ρ > ε_c: one metric, so the
    // split and merge thresholds and the scheduling of checks hold both rules.
    return std::max(error, spacing * coarseErrorPx() / m_options.maxSamplePx);
}

double LodQuadtree::decisionDistance(const Node& node) const {
    if (m_options.splitRule == SplitRule::LivnyEdges)
        return static_cast<const PlaneSurface&>(m_surface).edgeDistance(m_camera.position,
                                                                        node.volume);
    const double rho = m_surface.distance(m_camera.position, node.volume);
    // Where only the surface's curvature is left to split for (a bare or virtual patch, or
    // data without finer data), it is never worth splitting closer than a metre, or a camera
    // standing on such a patch would split it down to the deepest level.
    return node.finerData ? rho : std::max(rho, 1.0);
}

void LodQuadtree::schedule(int node, CheckKind kind, double travel) {
    // At least kMinTravelM ahead: a decision just made is not due again in the same frame
    // (the odometer stands still within a frame), so a frame's check loop always ends.
    pushCheck(node, kind, m_odometer + std::max(kMinTravelM, travel));
}

void LodQuadtree::pushCheck(int node, CheckKind kind, double atOdometer) {
    m_checks.push_back(
        {atOdometer, node, m_nodes[static_cast<std::size_t>(node)].generation, kind});
    std::push_heap(m_checks.begin(), m_checks.end(), laterCheck<Check, Check>);
}

// A leaf's split decision can change only once ρ falls to ρ_split = γ·Err/ε_c (ε_c: the
// coarse stage's threshold, LodOptions::coarseErrorPx). A leaf that can never split (the
// deepest level, or a child that failed to load) needs no check.
void LodQuadtree::scheduleLeaf(int index) {
    const Node& node = m_nodes[static_cast<std::size_t>(index)];
    if (node.splitBlocked || node.id.level >= m_surface.maxLevel()) return;
    const double rho = decisionDistance(node);
    const double rhoSplit = m_gamma * metricM(node) / coarseErrorPx();
    schedule(index, CheckKind::Split, rho - rhoSplit);
}

// A node whose children are all leaves may merge once ρ grows to ρ_merge = γ·Err·h/ε_c.
void LodQuadtree::scheduleMergeIfCandidate(int index) {
    const Node& node = m_nodes[static_cast<std::size_t>(index)];
    if (node.leaf() || m_options.splitToFinest) return;
    for (int i = 0; i < node.childCount; ++i) {
        if (!m_nodes[static_cast<std::size_t>(node.firstChild + i)].leaf()) return;
    }
    const double rho = decisionDistance(node);
    const double rhoMerge = m_gamma * metricM(node) * m_options.hysteresis / coarseErrorPx();
    schedule(index, CheckKind::Merge, rhoMerge - rho);
}

void LodQuadtree::makeDataNode(Node& node, const io::PatchId& id, const io::PatchInfo& info) {
    node.id = id;
    node.kind = NodeKind::Data;
    node.info = info;
    node.tile = id;
    node.layer = m_residency.layerOf(id);
    node.volume = m_surface.volume(id, info.minHeight, info.maxHeight);
    node.errorM = info.error;
    node.finerData = m_surface.hasFinerData(id, info);
    // Native tiles can take a finest patch's error down to theirs: its Err(P) is what a
    // split into them reduces.
    m_nativeScratch.clear();
    node.nativeCapable = !node.finerData && m_surface.nativeTilesOver(id, m_nativeScratch);
    node.rises = residentRises(id);
    node.splitM = node.finerData || node.nativeCapable
                      ? double(info.error)
                      : m_surface.flatTriangleError(id.level, node.rises);
    node.texelOffsetX = node.texelOffsetY = 0.0;
    node.texelStep = 1.0;
    m_residency.pin(id);
}

// `info`: the child's summary when the pyramid stores it (resident), else null: the child
// is then virtual under a parent with a tile, bare under a bare one.
void LodQuadtree::makeChild(Node& child, const Node& parent, const SurfaceChild& at,
                            const io::PatchInfo* info) {
    if (info != nullptr) {
        makeDataNode(child, at.id, *info);
        return;
    }
    child.id = at.id;
    child.finerData = false;
    // A virtual patch's samples interpolate its tile's between theirs, half as far apart as
    // its parent's: half the rise. A bare one is flat.
    child.rises = parent.kind == NodeKind::Bare
                      ? io::SampleRises{}
                      : io::SampleRises{0.5f * parent.rises.east, 0.5f * parent.rises.north};
    child.splitM = m_surface.flatTriangleError(at.id.level, child.rises);
    if (parent.kind == NodeKind::Bare) {
        child.kind = NodeKind::Bare;
        child.layer = -1;
        child.tile = at.id;
        child.errorM = static_cast<float>(child.splitM);
        child.volume = m_surface.volume(at.id, 0.0f, 0.0f);
        return;
    }
    // Virtual: this quadrant of the tile the parent draws.
    const double half = 0.5 * double(m_surface.layout().patchQuads()) * parent.texelStep;
    child.kind = NodeKind::Virtual;
    child.info = parent.info;
    child.tile = parent.tile;
    child.layer = parent.layer;
    child.texelStep = 0.5 * parent.texelStep;
    child.texelOffsetX = parent.texelOffsetX + double(at.quadrant & 1) * half;
    child.texelOffsetY = parent.texelOffsetY + double(at.quadrant >> 1) * half;
    child.errorM = parent.info.error;
    child.errorM += static_cast<float>(child.splitM);
    child.volume = m_surface.volume(at.id, parent.info.minHeight, parent.info.maxHeight);
}

void LodQuadtree::pinNative(const io::PatchId& tile) {
    for (NativePin& pin : m_nativePins)
        if (pin.tile == tile) {
            ++pin.holders;
            return;
        }
    const io::PatchInfo* info = m_residency.residentInfo(tile);
    TERRAIN_ASSERT(info != nullptr, "pinning a native tile that is not resident");
    m_residency.pin(tile);
    m_nativePins.push_back({tile, 1, m_windows.create(tile, *info, residentRises(tile))});
}

void LodQuadtree::unpinNative(const io::PatchId& tile) {
    for (auto it = m_nativePins.begin(); it != m_nativePins.end(); ++it)
        if (it->tile == tile) {
            if (--it->holders == 0) {
                m_windows.destroy(it->windows);
                m_residency.unpin(tile);
                m_nativePins.erase(it);
            }
            return;
        }
    TERRAIN_ASSERT(false, "unpinning a native tile no node pinned");
}

int LodQuadtree::trySplitNative(int index, double screenError) {
    m_nativeScratch.clear();
    m_surface.nativeTilesOver(m_nodes[static_cast<std::size_t>(index)].id, m_nativeScratch);
    bool allResident = true;
    for (const io::PatchId& tile : m_nativeScratch) {
        if (m_residency.acquire(tile, priorityOf(screenError)) != nullptr) continue;
        if (m_residency.hasFailed(tile)) return 0;
        allResident = false;
    }
    if (!allResident) {
        ++m_stats.waitingNativeSplits;
        return -1;
    }
    // What the tiles can come down to over the patch's ground. Split into windows
    // (NativeWindowTree), their flat triangles' terms shrink by a quarter a level toward 0,
    // and what stays is their Err(P), the other sources' miss, unless only their own source
    // shows over the patch. Drawn whole, their terms at their own samples stay too.
    const bool windows = refinesNativeWindows();
    const bool pure = windows && m_surface.nativeGroundIsPure(m_nodes[std::size_t(index)].id);
    double worst = 0.0;  // the tiles' own screen error, pixels
    for (const io::PatchId& tile : m_nativeScratch) {
        if (pure) break;
        const io::PatchInfo* info = m_residency.residentInfo(tile);
        // Each seen from where it lies: it reaches past the patch, over neighbours that may be
        // nearer the camera. No nearer than a metre, as for what only curvature is left to
        // split for (decisionDistance): a camera standing in a tile's box would see any error
        // as infinite, and a tile's error is mostly its flat triangles' bulge, millimetres.
        const double error =
            double(info->error) +
            (windows ? 0.0
                     : m_surface.nativeGeometricErrors(tile, *info, residentRises(tile), {}).fullM);
        const double rho = std::max(
            1.0,
            m_surface.distance(m_camera.position, m_surface.nativeTileVolume(tile, info->minHeight,
                                                                             info->maxHeight, {})));
        worst = std::max(worst, m_gamma * error / rho);
    }
    // Where the tiles show as much error as the patch, they gain nothing: the patch splits as
    // one without finer data does (for its curvature).
    if (worst >= screenError) return 0;
    for (const io::PatchId& tile : m_nativeScratch) pinNative(tile);
    const int first = allocateBlock();
    Node& parent = m_nodes[static_cast<std::size_t>(index)];  // allocateBlock may grow
    parent.firstChild = first;
    parent.childCount = 1;
    ++parent.generation;
    Node& child = m_nodes[static_cast<std::size_t>(first)];
    const std::uint32_t generation = child.generation;
    child = Node{};
    child.generation = generation + 1;
    child.parent = index;
    child.id = child.tile = parent.id;
    child.kind = NodeKind::Native;
    child.info = parent.info;
    child.layer = parent.layer;  // the parent's tile, pinned by it; the child draws the natives
    child.volume = parent.volume;
    child.visible = parent.visible;
    child.splitBlocked = true;  // nothing finer than the sources' own samples
    m_nativeTiles[first] = m_nativeScratch;
    std::vector<glm::dvec4>& footprints = m_nativeFootprints[first];
    footprints.clear();
    for (const io::PatchId& tile : m_nativeScratch)
        footprints.push_back(
            m_surface.nativeFootprintOn(parent.id, tile).value_or(glm::dvec4(0.0, 0.0, 1.0, 1.0)));
    ++m_stats.splits;
    const int grandparent = parent.parent;
    if (grandparent >= 0) ++m_nodes[static_cast<std::size_t>(grandparent)].generation;
    scheduleMergeIfCandidate(index);
    return 1;
}

io::SampleRises LodQuadtree::residentRises(const io::PatchId& id) const {
    // A residency that does not know a tile's heights (the tests' fakes) reports none: the
    // flat triangles' sag alone.
    return m_residency.residentSampleRises(id).value_or(io::SampleRises{});
}

bool LodQuadtree::refinesNativeWindows() const {
    return !m_options.splitToFinest && m_options.splitRule == SplitRule::ProjectedError;
}

void LodQuadtree::emitNative(int index, std::vector<PatchDraw>& out) {
    const auto tiles = m_nativeTiles.find(index);
    TERRAIN_ASSERT(tiles != m_nativeTiles.end(), "a native node without its tiles");
    NativeWindowTree::Walk walk;
    walk.view = &m_view;
    walk.camera = m_camera.position;
    walk.gamma = m_gamma;
    walk.thresholdPx = coarseErrorPx();
    walk.hysteresis = m_options.hysteresis;
    walk.horizonCulling = m_options.horizonCulling;
    walk.refine = refinesNativeWindows();
    for (const io::PatchId& tile : tiles->second) {
        if (std::any_of(m_nativeDrawn.begin(), m_nativeDrawn.end(),
                        [&](const NativeDrawn& d) { return d.tile == tile; }))
            continue;  // drawn for a neighbour already
        const io::PatchInfo* info = m_residency.residentInfo(tile);
        TERRAIN_ASSERT(info != nullptr, "a pinned native tile is not resident");
        const auto pin = std::find_if(m_nativePins.begin(), m_nativePins.end(),
                                      [&](const NativePin& p) { return p.tile == tile; });
        TERRAIN_ASSERT(pin != m_nativePins.end(), "a drawn native tile is not pinned");
        // Its windows split only over the ground of the patches that hold it.
        walk.focus = glm::dvec4(1e300, 1e300, -1e300, -1e300);
        for (const auto& [node, held] : m_nativeTiles)
            for (std::size_t t = 0; t < held.size(); ++t)
                if (held[t] == tile) {
                    const glm::dvec4& box = m_nativeFootprints.at(node)[t];
                    walk.focus =
                        glm::dvec4(std::min(walk.focus.x, box.x), std::min(walk.focus.y, box.y),
                                   std::max(walk.focus.z, box.z), std::max(walk.focus.w, box.w));
                }
        const std::size_t first = out.size();
        NativeWindowTree::Stats windows;
        m_windows.walk(pin->windows, walk,
                       PatchDraw::ofTile(tile, m_residency.layerOf(tile), *info), out, windows);
        m_nativeDrawn.push_back({tile, first, out.size() - first});
        m_stats.drawn += out.size() - first;
        m_stats.drawnNative += out.size() - first;
        m_stats.drawnNativeWindows += windows.drawnWindows;
        m_stats.deepestNativeWindow = std::max(m_stats.deepestNativeWindow, windows.deepest);
        m_stats.splits += windows.splits;
        m_stats.merges += windows.merges;
        m_stats.evaluations += windows.evaluations;
    }
}

// Every native node holding a drawn tile counts, in view or not: a patch culled behind the
// horizon or outside the frustum by its face box may still have part of the tile's surface
// in view (the tile's heights are not the face patch's), which its ground then keeps. A
// tile's windows own what it owns.
void LodQuadtree::assignNativeOwnerships(std::vector<PatchDraw>& out) {
    for (const NativeDrawn& drawn : m_nativeDrawn) {
        if (drawn.count == 0) continue;
        m_holderScratch.clear();
        for (const auto& [node, tiles] : m_nativeTiles)
            if (std::find(tiles.begin(), tiles.end(), drawn.tile) != tiles.end())
                m_holderScratch.push_back(m_nodes[static_cast<std::size_t>(node)].id);
        PatchDraw& first = out[drawn.first];
        assignNativeOwnership(first, m_holderScratch);
        for (std::size_t i = 1; i < drawn.count; ++i) {
            PatchDraw& window = out[drawn.first + i];
            window.imageryPatch = first.imageryPatch;
            window.nativeCells = first.nativeCells;
            window.nativeWindow = first.nativeWindow;
        }
    }
}

bool LodQuadtree::trySplit(int index, double screenError) {
    if (m_nodes[static_cast<std::size_t>(index)].nativeCapable &&
        m_nodes[static_cast<std::size_t>(index)].kind == NodeKind::Data) {
        const int native = trySplitNative(index, screenError);
        if (native != 0) return native > 0;
    }
    Node& node = m_nodes[static_cast<std::size_t>(index)];
    std::array<SurfaceChild, 4> children;
    const io::PatchInfo* infos[4] = {};
    const int count = m_surface.children(node.id, children);
    bool allResident = true;
    for (int i = 0; i < count; ++i) {
        const SurfaceChild& child = children[static_cast<std::size_t>(i)];
        if (node.kind != NodeKind::Data || !m_surface.storesChild(node.info, child.quadrant))
            continue;  // virtual or bare: no tile to wait for
        infos[i] = m_residency.acquire(child.id, priorityOf(screenError));
        if (infos[i] == nullptr && m_residency.hasFailed(child.id)) node.splitBlocked = true;
        allResident = allResident && infos[i] != nullptr;
    }
    if (!allResident) {
        // The levels under the children that will likely split too are read meanwhile, so
        // they split in the frame the children arrive instead of a frame a level (issue 49:
        // full detail soon after a teleport). On the sparse globe only a patch's parent
        // knows whether it is stored: those below the children may turn out absent.
        if (node.kind == NodeKind::Data)
            prefetchBelow(node.id, node.info, double(node.info.error), errorDecay(node),
                          kPrefetchLevels, &node.info);
        return false;
    }

    const int first = allocateBlock();
    {
        Node& parent = m_nodes[static_cast<std::size_t>(index)];  // allocateBlock may grow
        parent.firstChild = first;
        parent.childCount = static_cast<std::uint8_t>(count);
        ++parent.generation;
    }
    for (int i = 0; i < count; ++i) {
        Node& child = m_nodes[static_cast<std::size_t>(first + i)];
        const std::uint32_t generation = child.generation;  // stale checks must stay stale
        child = Node{};
        child.generation = generation + 1;
        child.parent = index;
        makeChild(child, m_nodes[static_cast<std::size_t>(index)],
                  children[static_cast<std::size_t>(i)], infos[i]);
        int planes = 0b11111;
        child.visible = !m_surface.outsideFrustum(m_view, child.volume, planes) &&
                        !(m_options.horizonCulling && m_surface.belowHorizon(m_view, child.volume));
    }
    ++m_stats.splits;
    // The grandparent is no longer a merge candidate: its pending merge check is stale.
    const int grandparent = m_nodes[static_cast<std::size_t>(index)].parent;
    if (grandparent >= 0) ++m_nodes[static_cast<std::size_t>(grandparent)].generation;
    // The children decide at once (a fast camera may need several levels in one frame).
    for (int i = 0; i < count; ++i) evaluateLeaf(first + i);
    scheduleMergeIfCandidate(index);
    return true;
}

// How a patch's Err(P) shrinks level by level below `node`, as far as its own ancestry
// shows: its error over its parent's, between a half (smooth terrain: errors halve with the
// spacing) and 1 (where a finer source or a cliff keeps the error from shrinking: a globe's
// coarse levels over a regional source keep theirs for several levels).
double LodQuadtree::errorDecay(const Node& node) const {
    if (node.parent < 0) return kHalving;
    const Node& parent = m_nodes[static_cast<std::size_t>(node.parent)];
    if (parent.kind != NodeKind::Data || !(parent.info.error > 0.0f)) return kHalving;
    return std::clamp(double(node.info.error) / double(parent.info.error), kHalving, 1.0);
}

// A prediction, not a bound (a wrong one costs a read, never the picture): a patch's Err(P)
// is its own where it is resident, else its parent's times `decay` (errorDecay), its
// box as the footprint over the ancestor's height range, and it will split if that error
// projected from its box exceeds ε_c. The children of each child predicted to split are
// prefetched, `levels` deep, ranked by that prediction below every want (prefetchPriority).
// `stored`: the info of `id` if known (resident), which says which children the pyramid
// stores (all on the plane; on the globe, those below an unknown patch may be absent, which
// the residency learns from the read and remembers: knownAbsent).
void LodQuadtree::prefetchBelow(const io::PatchId& id, const io::PatchInfo& heights, double errorM,
                                double decay, int levels, const io::PatchInfo* stored) {
    if (levels <= 0 || m_options.splitRule != SplitRule::ProjectedError) return;
    std::array<SurfaceChild, 4> children;
    const int count = m_surface.children(id, children);
    // Patches at the pyramid's finest level have no stored children (on the globe, whose
    // maxLevel lies deeper, the levels below are bare or an ancestor's tile: nothing to read).
    const int finestStored = m_surface.layout().finestLevel();
    for (int i = 0; i < count; ++i) {
        const SurfaceChild& at = children[static_cast<std::size_t>(i)];
        const io::PatchId child = at.id;
        if (child.level >= finestStored) continue;
        if (stored != nullptr && !m_surface.storesChild(*stored, at.quadrant)) continue;
        if (m_residency.knownAbsent(child)) continue;
        const PatchVolume volume = m_surface.volume(child, heights.minHeight, heights.maxHeight);
        int planes = 0b11111;
        if (m_surface.outsideFrustum(m_view, volume, planes)) continue;
        const io::PatchInfo* childInfo = m_residency.residentInfo(child);
        const double childErrorM = childInfo != nullptr ? double(childInfo->error) : decay * errorM;
        const double rho = m_surface.distance(m_camera.position, volume);
        const double predicted =
            rho <= 0.0 ? std::numeric_limits<double>::max() : m_gamma * childErrorM / rho;
        if (predicted <= coarseErrorPx()) continue;
        std::array<SurfaceChild, 4> grandchildren;
        const int below = m_surface.children(child, grandchildren);
        for (int k = 0; k < below; ++k) {
            const SurfaceChild& grandchild = grandchildren[static_cast<std::size_t>(k)];
            if (childInfo != nullptr && !m_surface.storesChild(*childInfo, grandchild.quadrant))
                continue;
            m_residency.prefetch(grandchild.id, prefetchPriority(predicted));
            ++m_stats.prefetched;
        }
        prefetchBelow(child, heights, childErrorM, decay, levels - 1, childInfo);
    }
}

// A drawn leaf the camera is heading for: if its projected error from where the camera will
// be LodOptions::readAheadFrames frames on, at its present velocity, exceeds ε_c, it will
// likely split by then, so its children are read ahead now and are there when it does (issue
// 49, prefetch along the camera's motion). A prediction, not a decision: a wrong one costs a
// read. One box distance per drawn leaf, and only while the camera moves.
void LodQuadtree::prefetchAlongMotion(const Node& leaf) {
    if (m_options.readAheadFrames <= 0.0 || m_motion == glm::dvec3(0.0) ||
        leaf.kind != NodeKind::Data || !(leaf.finerData || leaf.nativeCapable) || leaf.waiting ||
        leaf.splitBlocked || leaf.id.level >= m_surface.maxLevel() ||
        m_options.splitRule != SplitRule::ProjectedError || m_options.splitToFinest)
        return;
    const glm::dvec3 ahead = m_camera.position + m_options.readAheadFrames * m_motion;
    const double rho = m_surface.distance(ahead, leaf.volume);
    const double predicted =
        rho <= 0.0 ? std::numeric_limits<double>::max() : m_gamma * metricM(leaf) / rho;
    if (predicted <= coarseErrorPx()) return;
    if (!leaf.finerData) {  // a finest patch splits into the native tiles over it
        m_nativeScratch.clear();
        m_surface.nativeTilesOver(leaf.id, m_nativeScratch);
        for (const io::PatchId& tile : m_nativeScratch) {
            m_residency.prefetch(tile, prefetchPriority(predicted));
            ++m_stats.prefetched;
        }
        return;
    }
    std::array<SurfaceChild, 4> children;
    const int count = m_surface.children(leaf.id, children);
    for (int i = 0; i < count; ++i) {
        const SurfaceChild& child = children[static_cast<std::size_t>(i)];
        if (!m_surface.storesChild(leaf.info, child.quadrant)) continue;
        m_residency.prefetch(child.id, prefetchPriority(predicted));
        ++m_stats.prefetched;
    }
}

// A root on its way (a cold start, a teleport into a new pyramid): nothing is known of its
// errors yet, so the two levels under it in view are read meanwhile, whatever their error
// (20 tiles at most), and split at once if needed when the root arrives. On the globe,
// where every root is asked for at once, a root out of view waits for the view.
void LodQuadtree::prefetchUnderRoot(const io::PatchId& root) {
    if (m_residency.hasFailed(root) || m_surface.layout().finestLevel() <= root.level) return;
    io::PatchInfo wholeDem;
    wholeDem.minHeight = static_cast<float>(m_surface.manifest().statistics.minHeight);
    wholeDem.maxHeight = static_cast<float>(m_surface.manifest().statistics.maxHeight);
    int planes = 0b11111;
    if (m_surface.outsideFrustum(
            m_view, m_surface.volume(root, wholeDem.minHeight, wholeDem.maxHeight), planes))
        return;
    std::array<SurfaceChild, 4> children;
    const int count = m_surface.children(root, children);
    for (int i = 0; i < count; ++i) {
        m_residency.prefetch(children[static_cast<std::size_t>(i)].id,
                             prefetchPriority(std::numeric_limits<double>::infinity()));
        ++m_stats.prefetched;
    }
    prefetchBelow(root, wholeDem, std::numeric_limits<double>::infinity(), kHalving, 1, nullptr);
}

// A leaf wants its children at its screen error, above ε_c; a read ahead, predicted at
// `predicted` px, goes below every want and above none of the others' reads ahead with a
// larger prediction: ε_c · predicted / (predicted + ε_c), in (0, ε_c].
float LodQuadtree::prefetchPriority(double predicted) const {
    const double c = coarseErrorPx();
    return priorityOf(std::isinf(predicted) ? c : c * (predicted / (predicted + c)));
}

void LodQuadtree::evaluateLeaf(int index) {
    Node& node = m_nodes[static_cast<std::size_t>(index)];
    ++m_stats.evaluations;
    if (!node.visible) return;  // the culling walk re-evaluates it when it comes into view
    const double error = screenError(node);
    const bool wantsSplit = (m_options.splitToFinest || error > coarseErrorPx()) &&
                            node.id.level < m_surface.maxLevel() && !node.splitBlocked;
    if (wantsSplit && trySplit(index, error)) return;
    Node& again = m_nodes[static_cast<std::size_t>(index)];
    if (wantsSplit && !again.splitBlocked) {
        // Children on their way: retried every frame, which keeps their requests alive.
        ++m_stats.waitingSplits;
        if (!again.waiting) {
            again.waiting = true;
            m_waitingNext.push_back(index);
        }
        return;
    }
    scheduleLeaf(index);
}

void LodQuadtree::evaluateMerge(int index) {
    if (m_options.splitToFinest) return;  // the uniform grid merges only what leaves the view
    Node& node = m_nodes[static_cast<std::size_t>(index)];
    for (int i = 0; i < node.childCount; ++i) {
        if (!m_nodes[static_cast<std::size_t>(node.firstChild + i)].leaf())
            return;  // not a candidate
    }
    ++m_stats.evaluations;
    if (screenError(node) * m_options.hysteresis < coarseErrorPx()) {
        collapse(index);
        ++m_stats.merges;
        scheduleLeaf(index);
        const int parent = m_nodes[static_cast<std::size_t>(index)].parent;
        if (parent >= 0) {
            ++m_nodes[static_cast<std::size_t>(parent)].generation;
            scheduleMergeIfCandidate(parent);
        }
        return;
    }
    scheduleMergeIfCandidate(index);
}

// Removes every descendant of `index`, unpinning their tiles; `index` becomes a leaf.
void LodQuadtree::collapse(int index) {
    Node& node = m_nodes[static_cast<std::size_t>(index)];
    if (node.leaf()) return;
    const int first = node.firstChild;
    const int count = node.childCount;
    node.firstChild = -1;
    node.childCount = 0;
    ++node.generation;
    for (int i = 0; i < count; ++i) {
        collapse(first + i);
        Node& child = m_nodes[static_cast<std::size_t>(first + i)];
        if (child.kind == NodeKind::Data) m_residency.unpin(child.id);
        if (child.kind == NodeKind::Native) {
            const auto tiles = m_nativeTiles.find(first + i);
            TERRAIN_ASSERT(tiles != m_nativeTiles.end(), "a native node without its tiles");
            for (const io::PatchId& tile : tiles->second) unpinNative(tile);
            m_nativeTiles.erase(tiles);
            m_nativeFootprints.erase(first + i);
        }
        ++child.generation;  // its pending checks are stale now
        child.waiting = false;
        child.parent = kFreed;
    }
    freeBlock(first);
}

PatchDraw LodQuadtree::drawOf(const Node& node) const {
    PatchDraw draw;
    draw.id = node.id;
    draw.layer = node.layer;
    draw.errorM = node.errorM;
    draw.tileId = node.tile;
    if (node.kind != NodeKind::Bare) {
        draw.minHeight = node.info.minHeight;
        draw.maxHeight = node.info.maxHeight;
    }
    if (node.kind != NodeKind::Data)
        draw.bareBlockErrorsM = m_surface.flatTriangleBlockErrors(node.id.level, node.rises);
    if (node.kind == NodeKind::Virtual) {
        draw.isVirtual = true;
        draw.texelOffset = {static_cast<float>(node.texelOffsetX),
                            static_cast<float>(node.texelOffsetY)};
        draw.texelStep = static_cast<float>(node.texelStep);
    }
    return draw;
}

void LodQuadtree::cull(int index, int planeMask, std::vector<PatchDraw>& out) {
    Node& node = m_nodes[static_cast<std::size_t>(index)];
    ++m_stats.visited;
    const bool outside = m_surface.outsideFrustum(m_view, node.volume, planeMask);
    const bool hidden =
        !outside && m_options.horizonCulling && m_surface.belowHorizon(m_view, node.volume);
    if (outside || hidden) {
        if (!node.leaf()) {
            collapse(index);  // out of view: keep the pool for what is seen
            ++m_stats.merges;
        }
        node.visible = false;
        ++(outside ? m_stats.culled : m_stats.horizonCulled);
        m_stats.coverage += m_surface.coverageOf(node.id);
        return;
    }
    const bool cameIntoView = !node.visible;
    node.visible = true;
    if (node.leaf()) {
        if (cameIntoView) {
            ++node.generation;  // its old check assumed it was hidden
            evaluateLeaf(index);
        }
        const Node& now = m_nodes[static_cast<std::size_t>(index)];
        if (!now.leaf()) {  // split just now
            cull(index, planeMask, out);
            return;
        }
        if (now.kind == NodeKind::Native) {
            emitNative(index, out);
            m_stats.coverage += m_surface.coverageOf(now.id);
            return;
        }
        prefetchAlongMotion(now);
        out.push_back(drawOf(now));
        ++m_stats.drawn;
        m_stats.drawnBare += now.kind == NodeKind::Bare ? 1 : 0;
        m_stats.drawnVirtual += now.kind == NodeKind::Virtual ? 1 : 0;
        m_stats.deepestLevel = std::max(m_stats.deepestLevel, now.id.level);
        m_stats.coverage += m_surface.coverageOf(now.id);
        return;
    }
    if (screenError(node) <= coarseErrorPx()) ++m_stats.heldSplits;
    const int first = node.firstChild;
    const int count = node.childCount;
    for (int i = 0; i < count; ++i) cull(first + i, planeMask, out);
}

// The roots' nodes: resident roots as data; on a surface drawn bare meanwhile (the globe)
// the others bare until they arrive. False while the plane's root is on its way.
bool LodQuadtree::start() {
    const std::span<const io::PatchId> roots = m_surface.roots();
    std::vector<const io::PatchInfo*> infos(roots.size());
    for (std::size_t r = 0; r < roots.size(); ++r) {
        infos[r] = m_residency.acquire(roots[r], std::numeric_limits<float>::max());
        if (infos[r] == nullptr && !m_surface.drawsBareSurface()) {
            prefetchUnderRoot(roots[r]);
            return false;
        }
    }
    m_nodes.resize(static_cast<std::size_t>(m_rootSlots));
    for (int slot = 0; slot < m_rootSlots; ++slot) {
        Node& node = m_nodes[static_cast<std::size_t>(slot)];
        node = Node{};
        node.parent = kSpare;
        if (slot >= m_rootCount) continue;
        node.parent = -1;
        node.visible = true;
        const io::PatchId& id = roots[static_cast<std::size_t>(slot)];
        if (const io::PatchInfo* info = infos[static_cast<std::size_t>(slot)]) {
            makeDataNode(node, id, *info);
            continue;
        }
        node.id = node.tile = id;
        node.kind = NodeKind::Bare;
        node.awaitingTile = true;
        node.rises = {};
        node.splitM = m_surface.flatTriangleError(id.level, node.rises);
        node.errorM = static_cast<float>(node.splitM);
        node.volume = m_surface.volume(id, 0.0f, 0.0f);
    }
    m_started = true;
    m_recheckAll = true;
    return true;
}

// A root drawn bare until its tile arrived: its bare subtree gives way to the data.
void LodQuadtree::takeArrivedRoots() {
    for (int root = 0; root < m_rootCount; ++root) {
        Node& node = m_nodes[static_cast<std::size_t>(root)];
        if (!node.awaitingTile) continue;
        const io::PatchInfo* info = m_residency.acquire(node.id, std::numeric_limits<float>::max());
        if (info == nullptr) {
            prefetchUnderRoot(node.id);
            continue;
        }
        collapse(root);
        Node& arrived = m_nodes[static_cast<std::size_t>(root)];
        arrived.awaitingTile = false;
        arrived.splitBlocked = false;
        makeDataNode(arrived, arrived.id, *info);
        ++arrived.generation;
        pushCheck(root, CheckKind::Split, m_odometer);  // due now
    }
}

LodUpdateStats LodQuadtree::update(const Camera& camera, std::vector<PatchDraw>& out) {
    out.clear();
    m_nativeDrawn.clear();
    m_stats = {};
    m_motion = m_started ? camera.position - m_camera.position : glm::dvec3(0.0);
    m_odometer += glm::length(camera.position - m_camera.position);
    const double gamma = camera.errorScale();
    if (gamma != m_gamma) m_recheckAll = true;
    m_camera = camera;
    m_gamma = gamma;
    m_view = m_surface.view(camera);

    if (!m_started && !start()) return m_stats;
    takeArrivedRoots();

    if (m_recheckAll) {
        // γ or ε changed (or the first frame): every decision is evaluated again.
        m_checks.clear();
        for (std::size_t i = 0; i < m_nodes.size(); ++i) {
            Node& node = m_nodes[i];
            if (node.parent == kFreed || node.parent == kSpare) continue;
            ++node.generation;
            pushCheck(static_cast<int>(i), node.leaf() ? CheckKind::Split : CheckKind::Merge,
                      m_odometer);  // due now
        }
        m_recheckAll = false;
    }

    // Leaves waiting for children try again (and keep their requests wanted).
    m_waiting.swap(m_waitingNext);
    m_waitingNext.clear();
    for (const int index : m_waiting) {
        Node& node = m_nodes[static_cast<std::size_t>(index)];
        if (!node.waiting) continue;  // collapsed or freed meanwhile
        node.waiting = false;
        if (node.leaf() && node.parent != kFreed) evaluateLeaf(index);
    }

    // Decisions whose travel budget ran out.
    while (!m_checks.empty() && m_checks.front().atOdometer <= m_odometer) {
        std::pop_heap(m_checks.begin(), m_checks.end(), laterCheck<Check, Check>);
        const Check check = m_checks.back();
        m_checks.pop_back();
        const Node& node = m_nodes[static_cast<std::size_t>(check.node)];
        if (node.generation != check.generation || node.parent == kFreed) continue;  // stale
        if (check.kind == CheckKind::Split) {
            if (node.leaf() && !node.waiting) evaluateLeaf(check.node);
        } else {
            if (!node.leaf()) evaluateMerge(check.node);
        }
    }

    for (int root = 0; root < m_rootCount; ++root) cull(root, 0b11111, out);
    assignNativeOwnerships(out);
    std::uint64_t nodes = 0;
    for (const Node& node : m_nodes) nodes += node.parent >= -1 ? 1 : 0;
    m_stats.nodes = nodes;

    // Checks made stale by later decisions stay in the heap until due; drop them when they
    // outnumber the live ones, so the heap stays within its reserved storage.
    if (m_checks.size() > 2 * nodes + 64) {
        std::erase_if(m_checks, [this](const Check& c) {
            const Node& node = m_nodes[static_cast<std::size_t>(c.node)];
            return node.generation != c.generation || node.parent == kFreed;
        });
        std::make_heap(m_checks.begin(), m_checks.end(), laterCheck<Check, Check>);
    }
    return m_stats;
}

std::optional<std::string> LodQuadtree::checkInvariants() const {
    if (!m_started) return std::nullopt;
    std::uint64_t covered = 0;
    std::vector<int> stack;
    for (int root = 0; root < m_rootCount; ++root) stack.push_back(root);
    while (!stack.empty()) {
        const int index = stack.back();
        stack.pop_back();
        const Node& node = m_nodes[static_cast<std::size_t>(index)];
        const std::string name = "L" + std::to_string(node.id.level) + " (" +
                                 std::to_string(node.id.x) + ", " + std::to_string(node.id.y) + ")";
        if (node.kind != NodeKind::Bare && (m_residency.residentInfo(node.tile) == nullptr ||
                                            m_residency.layerOf(node.tile) != node.layer)) {
            return "tree node " + name + " is not resident on its layer";
        }
        if (node.kind == NodeKind::Data && !m_residency.isPinned(node.id))
            return "tree node " + name + " is not pinned";
        if (node.kind == NodeKind::Native) {
            std::vector<io::PatchId> tiles;
            const auto held = m_nativeTiles.find(index);
            if (!m_surface.nativeTilesOver(node.id, tiles) || held == m_nativeTiles.end() ||
                held->second != tiles)
                return "native node " + name + " does not hold its native tiles";
            for (const io::PatchId& tile : tiles) {
                if (!m_residency.isPinned(tile) || m_residency.residentInfo(tile) == nullptr)
                    return "a native tile of " + name + " is not pinned and resident";
                const auto pin = std::find_if(m_nativePins.begin(), m_nativePins.end(),
                                              [&](const NativePin& p) { return p.tile == tile; });
                if (pin == m_nativePins.end()) return "a native tile of " + name + " has no pin";
                if (const auto broken = m_windows.check(pin->windows))
                    return "a native tile of " + name + ": " + *broken;
            }
        }
        if (node.childCount == 1 &&
            m_nodes[static_cast<std::size_t>(node.firstChild)].kind == NodeKind::Native) {
            const Node& child = m_nodes[static_cast<std::size_t>(node.firstChild)];
            if (!(child.id == node.id) || child.parent != index || !node.nativeCapable)
                return "node " + name + " has a wrong native child";
            stack.push_back(node.firstChild);
            continue;
        }
        if (node.leaf()) {
            covered += m_surface.coverageOf(node.id);
            continue;
        }
        std::array<SurfaceChild, 4> children;
        const int count = m_surface.children(node.id, children);
        if (count != node.childCount) return "node " + name + " has an incomplete set of children";
        for (int i = 0; i < count; ++i) {
            const Node& child = m_nodes[static_cast<std::size_t>(node.firstChild + i)];
            if (!(child.id == children[static_cast<std::size_t>(i)].id) || child.parent != index) {
                return "node " + name + " has a wrong child or parent link";
            }
            stack.push_back(node.firstChild + i);
        }
    }
    if (covered != m_surface.wholeCoverage()) {
        return "leaves cover " + std::to_string(covered) + " of " +
               std::to_string(m_surface.wholeCoverage()) + " of the surface";
    }
    return std::nullopt;
}

}  // namespace terrain::runtime
