// LodQuadtree: nodes in blocks of four, a min-heap of checks keyed on camera travel, a list
// of leaves waiting for their children, and a culling walk that emits the draw list.
#include "terrain/runtime/LodQuadtree.h"

#include "terrain/base/Assert.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace terrain::runtime {
namespace {

constexpr int kBlock = 4;
constexpr double kMinTravelM = 1e-3;

bool laterCheck(const auto& a, const auto& b) { return a.atOdometer > b.atOdometer; }

float priorityOf(double screenError) {
    return static_cast<float>(std::min(screenError, double{std::numeric_limits<float>::max()}));
}

}  // namespace

LodQuadtree::LodQuadtree(TileResidency& residency, const TerrainGeometry& geometry,
                         LodOptions options)
    : m_residency(residency), m_geometry(geometry), m_options(options) {
    TERRAIN_ASSERT(options.errorPx > 0.0 && options.coarseShare > 0.0 &&
                       options.coarseShare <= 1.0 && options.hysteresis >= 1.0,
                   "LodQuadtree: bad options");
    const auto capacity = static_cast<std::size_t>(residency.capacity());
    m_nodes.reserve(kBlock * (capacity + 1));
    m_freeBlocks.reserve(capacity + 1);
    m_checks.reserve(4 * capacity + 16);
    m_waiting.reserve(capacity + 1);
    m_waitingNext.reserve(capacity + 1);
}

LodQuadtree::~LodQuadtree() {
    if (!m_haveRoot) return;
    collapse(0);
    m_residency.unpin(m_nodes[0].id);
}

void LodQuadtree::setOptions(const LodOptions& options) {
    TERRAIN_ASSERT(options.errorPx > 0.0 && options.coarseShare > 0.0 &&
                       options.coarseShare <= 1.0 && options.hysteresis >= 1.0,
                   "LodQuadtree: bad options");
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
    if (m_options.splitRule == SplitRule::ProjectedError) return static_cast<double>(node.errorM);
    const glm::dvec2 spacing = m_geometry.sampleSpacing() *
                               static_cast<double>(m_geometry.layout().levelStep(node.id.level));
    return std::max(spacing.x, spacing.y);
}

double LodQuadtree::decisionDistance(const Node& node) const {
    if (m_options.splitRule != SplitRule::LivnyEdges)
        return distanceToBox(m_camera.position, node.box);
    return livnyEdgeDistance(m_camera.position, node.box, m_geometry.minHeight(),
                             m_geometry.maxHeight());
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
// coarse stage's threshold, LodOptions::coarseErrorPx). A leaf that
// can never split (the finest level, or a child that failed to load) needs no check.
void LodQuadtree::scheduleLeaf(int index) {
    const Node& node = m_nodes[static_cast<std::size_t>(index)];
    if (node.splitBlocked || node.id.level >= m_geometry.layout().finestLevel()) return;
    const double rho = decisionDistance(node);
    const double rhoSplit = m_gamma * metricM(node) / m_options.coarseErrorPx();
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
    const double rhoMerge =
        m_gamma * metricM(node) * m_options.hysteresis / m_options.coarseErrorPx();
    schedule(index, CheckKind::Merge, rhoMerge - rho);
}

bool LodQuadtree::trySplit(int index, double screenError) {
    Node& node = m_nodes[static_cast<std::size_t>(index)];
    io::PatchId children[4];
    const io::PatchInfo* infos[4] = {};
    const int count = containedChildren(m_geometry.layout(), node.id, children);
    bool allResident = true;
    for (int i = 0; i < count; ++i) {
        infos[i] = m_residency.acquire(children[i], priorityOf(screenError));
        if (infos[i] == nullptr && m_residency.hasFailed(children[i])) node.splitBlocked = true;
        allResident = allResident && infos[i] != nullptr;
    }
    if (!allResident) return false;

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
        child.id = children[i];
        child.box = m_geometry.patchBounds(children[i], *infos[i]);
        child.errorM = infos[i]->error;
        child.layer = m_residency.layerOf(children[i]);
        child.parent = index;
        child.visible = m_frustum.intersects(child.box);
        m_residency.pin(children[i]);
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

void LodQuadtree::evaluateLeaf(int index) {
    Node& node = m_nodes[static_cast<std::size_t>(index)];
    ++m_stats.evaluations;
    if (!node.visible) return;  // the culling walk re-evaluates it when it comes into view
    const double error = screenError(node);
    const bool wantsSplit = (m_options.splitToFinest || error > m_options.coarseErrorPx()) &&
                            node.id.level < m_geometry.layout().finestLevel() && !node.splitBlocked;
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
    if (screenError(node) * m_options.hysteresis < m_options.coarseErrorPx()) {
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

// Removes every descendant of `index`, unpinning their layers; `index` becomes a leaf.
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
        m_residency.unpin(child.id);
        ++child.generation;  // its pending checks are stale now
        child.waiting = false;
        child.parent = -2;  // freed
    }
    freeBlock(first);
}

void LodQuadtree::cull(int index, int planeMask, std::vector<PatchDraw>& out) {
    Node& node = m_nodes[static_cast<std::size_t>(index)];
    // Plane mask: planes the parent's box was entirely inside need no test for the child.
    for (int p = 0; p < 5; ++p) {
        if ((planeMask & (1 << p)) == 0) continue;
        const glm::dvec4& plane = m_frustum.planes[static_cast<std::size_t>(p)];
        const glm::dvec3 far{plane.x >= 0.0 ? node.box.max.x : node.box.min.x,
                             plane.y >= 0.0 ? node.box.max.y : node.box.min.y,
                             plane.z >= 0.0 ? node.box.max.z : node.box.min.z};
        if (plane.x * far.x + plane.y * far.y + plane.z * far.z + plane.w < 0.0) {
            if (!node.leaf()) {
                collapse(index);  // out of view: keep the pool for what is seen
                ++m_stats.merges;
            }
            node.visible = false;
            ++m_stats.culled;
            m_stats.coveredFinestPatches += finestPatchesCovered(m_geometry.layout(), node.id);
            return;
        }
        const glm::dvec3 near{plane.x >= 0.0 ? node.box.min.x : node.box.max.x,
                              plane.y >= 0.0 ? node.box.min.y : node.box.max.y,
                              plane.z >= 0.0 ? node.box.min.z : node.box.max.z};
        if (plane.x * near.x + plane.y * near.y + plane.z * near.z + plane.w >= 0.0) {
            planeMask &= ~(1 << p);
        }
    }
    const bool cameIntoView = !node.visible;
    node.visible = true;
    if (node.leaf()) {
        if (cameIntoView) {
            ++node.generation;  // its old check assumed it was hidden
            evaluateLeaf(index);
        }
        Node& now = m_nodes[static_cast<std::size_t>(index)];
        if (!now.leaf()) {  // split just now
            cull(index, planeMask, out);
            return;
        }
        out.push_back(
            {.id = now.id, .layer = now.layer, .errorM = now.errorM, .skirtDepthM = 0.0f});
        ++m_stats.drawn;
        m_stats.coveredFinestPatches += finestPatchesCovered(m_geometry.layout(), now.id);
        return;
    }
    const int first = node.firstChild;
    const int count = node.childCount;
    for (int i = 0; i < count; ++i) cull(first + i, planeMask, out);
}

LodUpdateStats LodQuadtree::update(const Camera& camera, std::vector<PatchDraw>& out) {
    out.clear();
    m_stats = {};
    m_odometer += glm::length(camera.position - m_camera.position);
    const double gamma = camera.errorScale();
    if (gamma != m_gamma) m_recheckAll = true;
    m_camera = camera;
    m_gamma = gamma;
    m_frustum = camera.frustum();

    if (!m_haveRoot) {
        const io::PatchId root{0, 0, 0};
        const io::PatchInfo* info = m_residency.acquire(root, std::numeric_limits<float>::max());
        if (info == nullptr) return m_stats;
        m_nodes.resize(kBlock);  // block 0 holds the root alone
        Node& node = m_nodes[0];
        node = Node{};
        node.id = root;
        node.box = m_geometry.patchBounds(root, *info);
        node.errorM = info->error;
        node.layer = m_residency.layerOf(root);
        node.visible = true;
        m_residency.pin(root);
        m_haveRoot = true;
        m_recheckAll = true;
    }

    if (m_recheckAll) {
        // γ or ε changed (or the first frame): every decision is evaluated again.
        m_checks.clear();
        for (std::size_t i = 0; i < m_nodes.size(); ++i) {
            Node& node = m_nodes[i];
            if (node.parent == -2 || (i > 0 && i < kBlock)) continue;  // free, or block 0's spares
            if (i > 0 && node.parent < 0) continue;
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
        if (node.leaf() && node.parent != -2) evaluateLeaf(index);
    }

    // Decisions whose travel budget ran out.
    while (!m_checks.empty() && m_checks.front().atOdometer <= m_odometer) {
        std::pop_heap(m_checks.begin(), m_checks.end(), laterCheck<Check, Check>);
        const Check check = m_checks.back();
        m_checks.pop_back();
        const Node& node = m_nodes[static_cast<std::size_t>(check.node)];
        if (node.generation != check.generation || node.parent == -2) continue;  // stale
        if (check.kind == CheckKind::Split) {
            if (node.leaf() && !node.waiting) evaluateLeaf(check.node);
        } else {
            if (!node.leaf()) evaluateMerge(check.node);
        }
    }

    cull(0, 0b11111, out);
    std::uint64_t nodes = 0;
    for (std::size_t i = 0; i < m_nodes.size(); ++i) {
        if (i == 0 || (i >= kBlock && m_nodes[i].parent >= 0)) ++nodes;
    }
    m_stats.nodes = nodes;

    // Checks made stale by later decisions stay in the heap until due; drop them when they
    // outnumber the live ones, so the heap stays within its reserved storage.
    if (m_checks.size() > 2 * nodes + 64) {
        std::erase_if(m_checks, [this](const Check& c) {
            const Node& node = m_nodes[static_cast<std::size_t>(c.node)];
            return node.generation != c.generation || node.parent == -2;
        });
        std::make_heap(m_checks.begin(), m_checks.end(), laterCheck<Check, Check>);
    }
    return m_stats;
}

std::optional<std::string> LodQuadtree::checkInvariants() const {
    if (!m_haveRoot) return std::nullopt;
    std::uint64_t covered = 0;
    std::vector<int> stack{0};
    while (!stack.empty()) {
        const int index = stack.back();
        stack.pop_back();
        const Node& node = m_nodes[static_cast<std::size_t>(index)];
        const std::string name = "L" + std::to_string(node.id.level) + " (" +
                                 std::to_string(node.id.x) + ", " + std::to_string(node.id.y) + ")";
        if (m_residency.residentInfo(node.id) == nullptr ||
            m_residency.layerOf(node.id) != node.layer) {
            return "tree node " + name + " is not resident on its layer";
        }
        if (!m_residency.isPinned(node.id)) return "tree node " + name + " is not pinned";
        if (node.leaf()) {
            covered += finestPatchesCovered(m_geometry.layout(), node.id);
            continue;
        }
        io::PatchId children[4];
        const int count = containedChildren(m_geometry.layout(), node.id, children);
        if (count != node.childCount) return "node " + name + " has an incomplete set of children";
        for (int i = 0; i < count; ++i) {
            const Node& child = m_nodes[static_cast<std::size_t>(node.firstChild + i)];
            if (!(child.id == children[i]) || child.parent != index) {
                return "node " + name + " has a wrong child or parent link";
            }
            stack.push_back(node.firstChild + i);
        }
    }
    const std::uint64_t domain = finestPatchesCovered(m_geometry.layout(), {0, 0, 0});
    if (covered != domain) {
        return "leaves cover " + std::to_string(covered) + " of " + std::to_string(domain) +
               " finest-level patches";
    }
    return std::nullopt;
}

}  // namespace terrain::runtime
