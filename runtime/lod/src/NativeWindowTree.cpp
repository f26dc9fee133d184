// NativeWindowTree: windows in blocks of four with a free list, walked top-down each frame.
#include "terrain/runtime/NativeWindowTree.h"

#include "terrain/base/Assert.h"
#include "terrain/pyramid/PatchErrors.h"

#include <algorithm>
#include <cmath>

namespace terrain::runtime {
namespace {

constexpr int kWindowBlock = 4;

}  // namespace

int NativeWindowTree::allocate() {
    if (!m_free.empty()) {
        const int first = m_free.back();
        m_free.pop_back();
        return first;
    }
    const int first = static_cast<int>(m_windows.size());
    m_windows.resize(m_windows.size() + kWindowBlock);
    return first;
}

void NativeWindowTree::release(int first) {
    for (int i = 0; i < kWindowBlock; ++i)
        m_windows[static_cast<std::size_t>(first + i)].alive = false;
    m_free.push_back(first);
}

void NativeWindowTree::make(Window& window, const Tile& tile, const globe::NativeWindow& at) const {
    window = Window{};
    window.alive = true;
    window.window = at;
    window.volume =
        m_surface.nativeTileVolume(tile.id, tile.info.minHeight, tile.info.maxHeight, at);
    const Surface::NativeGeometricErrors geometric =
        m_surface.nativeGeometricErrors(tile.id, tile.info, tile.rises, at);
    window.splitM = geometric.fullM;
    // The other sources' miss (the tile's Err(P)) cannot shrink by splitting: it stays where
    // one of them shows in the window.
    const double irreducible =
        m_surface.nativeWindowIsPure(tile.id, at) ? 0.0 : double(tile.info.error);
    window.errorM = io::roundUpToFloat(irreducible + geometric.fullM);
    window.blocksM = geometric.blocksM;
    if (at.depth > 0) {
        // A cell's twist h00 + h11 − h10 − h01 is at most twice its rise either way; along an
        // edge the sources' surface bends by it where the edge crosses the cell's diagonal, and
        // a drawn segment of L cells (at most 2^(3 − depth): a block's 8 quads simplified, or
        // a whole cell, beyond which the tile's λ holds) misses the bend by twist · L / 4.
        const double twist = 2.0 * double(std::min(tile.rises.east, tile.rises.north));
        const double cells = std::min(1.0, std::ldexp(1.0, 3 - at.depth));
        window.seamGapM = io::roundUpToFloat(0.25 * twist * cells);
    }
}

int NativeWindowTree::create(const io::PatchId& tile, const io::PatchInfo& info,
                             const io::SampleRises& rises) {
    const int root = allocate();
    const Tile owner{tile, info, rises};
    make(m_windows[static_cast<std::size_t>(root)], owner, globe::NativeWindow{});
    m_tiles.emplace_back(root, owner);
    return root;
}

void NativeWindowTree::destroy(int root) {
    collapse(root);
    release(root);
    const auto it = std::find_if(m_tiles.begin(), m_tiles.end(),
                                 [&](const auto& entry) { return entry.first == root; });
    TERRAIN_ASSERT(it != m_tiles.end(), "destroying a window tree that does not exist");
    m_tiles.erase(it);
}

int NativeWindowTree::collapse(int index) {
    Window& window = m_windows[static_cast<std::size_t>(index)];
    if (window.leaf()) return 0;
    const int first = window.firstChild;
    window.firstChild = -1;
    int freed = kWindowBlock;
    for (int i = 0; i < kWindowBlock; ++i) freed += collapse(first + i);
    release(first);
    return freed;
}

void NativeWindowTree::walk(int root, const Walk& walk, const PatchDraw& tile,
                            std::vector<PatchDraw>& out, Stats& stats) {
    const auto it = std::find_if(m_tiles.begin(), m_tiles.end(),
                                 [&](const auto& entry) { return entry.first == root; });
    TERRAIN_ASSERT(it != m_tiles.end(), "walking a window tree that does not exist");
    visit(root, it->second, walk, tile, out, stats);
}

void NativeWindowTree::visit(int index, Tile& tile, const Walk& walk, const PatchDraw& base,
                             std::vector<PatchDraw>& out, Stats& stats) {
    ++stats.evaluations;
    {
        const Window& window = m_windows[static_cast<std::size_t>(index)];
        int planes = 0b11111;
        if (m_surface.outsideFrustum(*walk.view, window.volume, planes) ||
            (walk.horizonCulling && m_surface.belowHorizon(*walk.view, window.volume))) {
            if (!window.leaf()) ++stats.merges;
            tile.windows -= collapse(index);  // out of view: nothing kept under it
            return;
        }
    }
    Window& window = m_windows[static_cast<std::size_t>(index)];
    // No nearer than a metre, as for every error only curvature is left to split for
    // (LodQuadtree::decisionDistance): a camera standing in a window's box would split it to
    // the deepest level.
    const double rho = std::max(1.0, m_surface.distance(walk.camera, window.volume));
    const double screen = walk.gamma * window.splitM / rho;
    const globe::NativeWindow& at = window.window;
    const bool focused = at.u0() <= walk.focus.z && at.u0() + at.size() >= walk.focus.x &&
                         at.v0() <= walk.focus.w && at.v0() + at.size() >= walk.focus.y;
    if (window.leaf()) {
        const bool split = walk.refine && focused && screen > walk.thresholdPx &&
                           at.depth < globe::NativeWindow::kMaxDepth &&
                           tile.windows + kWindowBlock <= kMaxWindowsPerTile;
        if (!split) {
            emit(window, base, out, stats);
            return;
        }
        const globe::NativeWindow parent = at;
        const int first = allocate();  // may move m_windows
        for (int q = 0; q < kWindowBlock; ++q)
            make(m_windows[static_cast<std::size_t>(first + q)], tile, parent.child(q));
        m_windows[static_cast<std::size_t>(index)].firstChild = first;
        tile.windows += kWindowBlock;
        ++stats.splits;
    } else {
        bool childrenAreLeaves = true;
        for (int q = 0; q < kWindowBlock; ++q)
            childrenAreLeaves = childrenAreLeaves &&
                                m_windows[static_cast<std::size_t>(window.firstChild + q)].leaf();
        if (!walk.refine || !focused ||
            (childrenAreLeaves && screen * walk.hysteresis < walk.thresholdPx)) {
            tile.windows -= collapse(index);
            ++stats.merges;
            emit(m_windows[static_cast<std::size_t>(index)], base, out, stats);
            return;
        }
    }
    const int first = m_windows[static_cast<std::size_t>(index)].firstChild;
    for (int q = 0; q < kWindowBlock; ++q) visit(first + q, tile, walk, base, out, stats);
}

void NativeWindowTree::emit(const Window& window, const PatchDraw& base,
                            std::vector<PatchDraw>& out, Stats& stats) const {
    PatchDraw draw = base;
    draw.errorM = window.errorM;
    draw.bareBlockErrorsM = window.blocksM;
    draw.seamGapM = window.seamGapM;
    const globe::NativeWindow& at = window.window;
    if (at.depth > 0) {
        // Drawn from the tile's samples as a virtual patch draws its ancestor's: the window's
        // sample s over the tile's offset + s · step (exact in float, NativeWindow::kMaxDepth).
        const double quads = double(m_surface.layout().patchQuads());
        draw.isVirtual = true;
        draw.texelOffset = {static_cast<float>(at.u0() * quads),
                            static_cast<float>(at.v0() * quads)};
        draw.texelStep = static_cast<float>(at.size());
        ++stats.drawnWindows;
        stats.deepest = std::max(stats.deepest, at.depth);
    }
    out.push_back(draw);
}

std::optional<std::string> NativeWindowTree::check(int root) const {
    // Each leaf of depth k covers 4^(kMax − k) of the tile's 4^kMax smallest windows.
    const auto area = [](int depth) {
        return std::uint64_t{1} << (2 * (globe::NativeWindow::kMaxDepth - depth));
    };
    std::uint64_t covered = 0;
    int alive = 0;
    std::vector<int> stack{root};
    while (!stack.empty()) {
        const int index = stack.back();
        stack.pop_back();
        const Window& window = m_windows[static_cast<std::size_t>(index)];
        if (!window.alive) return "a native window in the tree is freed";
        ++alive;
        if (window.window.depth > globe::NativeWindow::kMaxDepth)
            return "a native window is deeper than the cap";
        if (window.leaf()) {
            covered += area(window.window.depth);
            continue;
        }
        for (int q = 0; q < kWindowBlock; ++q) {
            const Window& child = m_windows[static_cast<std::size_t>(window.firstChild + q)];
            if (!(child.window == window.window.child(q)))
                return "a native window's child is not its quadrant";
            stack.push_back(window.firstChild + q);
        }
    }
    if (covered != area(0)) return "a native tile's windows do not tile it";
    const auto it = std::find_if(m_tiles.begin(), m_tiles.end(),
                                 [&](const auto& entry) { return entry.first == root; });
    if (it == m_tiles.end() || it->second.windows != alive)
        return "a native tile's window count is not its tree's";
    return std::nullopt;
}

std::size_t NativeWindowTree::windows() const {
    return static_cast<std::size_t>(
        std::count_if(m_windows.begin(), m_windows.end(), [](const Window& w) { return w.alive; }));
}

}  // namespace terrain::runtime
