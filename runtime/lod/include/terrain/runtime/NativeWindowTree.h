// NativeWindowTree: native tiles that split below their samples (docs/globe.md, "Native
// windows"). A native tile (a source's own longitude/latitude grid, "Native leaves") draws its
// samples as they are; near the ground its flat triangles still stray from the sources' own
// triangles on the ellipsoid by their sag and slope terms (Surface::nativeGeometricErrors),
// metres for a 3″ tile, tens of metres for a 20′ one. A window is a quarter of a tile, a
// quarter of that, and so on (globe::NativeWindow): drawn as a patch of its own, its vertices
// interpolate the tile's samples on the sources' own triangles (shaders/terrain_heights.glsl,
// heightInTriangles), so each of its flat triangles lies within one source triangle's plane
// and strays only by the geometric terms at its own size, a quarter per level.
//
// One tree per pinned tile, whichever finest face patches hold it: its windows split where
// γ · E_geo / ρ exceeds the threshold and merge back below it over the hysteresis, all within
// the frame (every window draws the pinned tile's layer: nothing to wait for), and are culled
// by their own boxes. A window's drawn error is its geometric error plus, where it is not pure
// (Surface::nativeWindowIsPure: another source shows in it), the tile's Err(P), which no split
// reduces. Render thread only; allocates nothing per frame once grown.
#pragma once

#include "terrain/globe/NativeOffset.h"
#include "terrain/pyramid/PatchRecord.h"
#include "terrain/runtime/PatchDraw.h"
#include "terrain/runtime/Surface.h"

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace terrain::runtime {

class NativeWindowTree {
public:
    /// What a frame's walk decides by.
    struct Walk {
        const SurfaceView* view = nullptr;
        glm::dvec3 camera{0.0};
        double gamma = 0.0;        ///< pixels a metre at a metre (Camera::errorScale)
        double thresholdPx = 1.0;  ///< split above γ · E_geo / ρ > this
        double hysteresis = 1.25;  ///< merge below threshold / hysteresis
        bool horizonCulling = true;
        /// False: the tile is drawn whole (its root window), as methods without this
        /// projected-error rule draw it.
        bool refine = true;
        /// Where windows may split, tile coordinates (u min, v min, u max, v max): the ground
        /// of the face patches the tile stands for. Elsewhere its windows draw nothing the
        /// patches own (NativeOwnership.h), and near a pole a longitude/latitude grid's
        /// bound grows without limit.
        glm::dvec4 focus{0.0, 0.0, 1.0, 1.0};
    };
    /// The most windows one tile keeps: a guard against a bound that would split without
    /// end (the deepest windows, 16 levels down, are a few hundred per tile near the camera).
    static constexpr int kMaxWindowsPerTile = 1024;
    struct Stats {
        std::uint64_t splits = 0;
        std::uint64_t merges = 0;
        std::uint64_t evaluations = 0;
        std::uint64_t drawnWindows = 0;  ///< drawn windows below a whole tile
        int deepest = 0;                 ///< the deepest drawn window's depth
    };

    explicit NativeWindowTree(const Surface& surface) : m_surface(surface) {}

    /// The root window of native tile `tile` (resident: `info` its summary, `rises` its
    /// samples' steepest rises). Returns its handle.
    int create(const io::PatchId& tile, const io::PatchInfo& info, const io::SampleRises& rises);
    /// Frees a root and every window under it.
    void destroy(int root);

    /// Updates root's windows for this frame and appends the visible leaves to `out`, each as
    /// `tile` (PatchDraw::ofTile of the tile) drawn over its window.
    void walk(int root, const Walk& walk, const PatchDraw& tile, std::vector<PatchDraw>& out,
              Stats& stats);

    /// The first broken invariant of root's tree, or nullopt: complete sets of four children
    /// at the next depth, leaves that tile the tile exactly, depth ≤ NativeWindow::kMaxDepth.
    std::optional<std::string> check(int root) const;
    /// Windows alive, roots included.
    std::size_t windows() const;

private:
    struct Window {
        globe::NativeWindow window;
        PatchVolume volume;
        double splitM = 0.0;             // its geometric error: what a split reduces
        float errorM = 0.0f;             // as drawn: its geometric error, plus the tile's if impure
        std::array<float, 4> blocksM{};  // its geometric error over blocks simplified by 2^d
        float seamGapM = 0.0f;           // PatchDraw::seamGapM
        int firstChild = -1;             // four consecutive
        bool alive = false;
        bool leaf() const { return firstChild < 0; }
    };

    // Whose windows a root's are: the tile's id and what its windows' errors come from.
    struct Tile {
        io::PatchId id;
        io::PatchInfo info;
        io::SampleRises rises;
        int windows = 1;  // alive in its tree, the root's included
    };

    int allocate();
    void release(int first);
    void make(Window& window, const Tile& tile, const globe::NativeWindow& at) const;
    /// Frees every window under `index`; returns how many.
    int collapse(int index);
    void visit(int index, Tile& tile, const Walk& walk, const PatchDraw& base,
               std::vector<PatchDraw>& out, Stats& stats);
    void emit(const Window& window, const PatchDraw& base, std::vector<PatchDraw>& out,
              Stats& stats) const;

    const Surface& m_surface;
    std::vector<Window> m_windows;              // blocks of four; a root takes a block of its own
    std::vector<int> m_free;                    // free blocks' first windows
    std::vector<std::pair<int, Tile>> m_tiles;  // by root
};

}  // namespace terrain::runtime
