// LodMethod: the LOD strategies a frame can be drawn with (DESIGN.md, "LOD strategies and
// comparison methods"), by the names the programs' --method and --methods flags take. Every
// method selects with its own published metric and is measured with the same harness
// (docs/lod-methods.md).
#pragma once

#include "terrain/base/Result.h"
#include "terrain/runtime/Surface.h"

#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace terrain::runtime {

enum class LodMethod {
    /// Yusov & Shevtsov 2011: patch quadtree (coarse) + per-edge tessellation from block
    /// errors (fine); ε split between the two stages. The default.
    Yusov2011,
    /// Ulrich 2002, "Rendering massive terrains using chunked level of detail control": the
    /// same quadtree of chunks, a chunk split while its geometric error projects to more than
    /// τ; each chunk drawn as its full mesh with skirts, no fine stage.
    ChunkedLod,
    /// The uniform full-resolution grid: every finest-level patch in view, fully tessellated.
    Uniform,
    /// Livny et al. 2007, seamless patches: the patch quadtree chosen on the CPU by Eq. 1
    /// (ε = ρ · l / d per edge), each patch four triangular tiles at their edges'
    /// resolutions (two: R_max and R_max / 2), heights fetched from the patch's texture.
    Livny2007,
    /// Valdetaro et al. 2011, local parallel tessellation: a flat grid of tiles (the finest
    /// patches, cut in tiles of 64 quads) with no hierarchy, each tile's factors from its
    /// height-acceleration map (Sobel of Sobel), its screen error and its distance (§4–5).
    Valdetaro2011,
    /// Strugar 2009, CDLOD: the patch quadtree by distance ranges doubling level by level,
    /// each patch a regular grid whose vertices morph towards the coarser level's grid near
    /// the end of its range; no tessellation, no skirts.
    Cdlod,
    /// Lee & Shin 2011, geometry splitting: the quadtree of the whole finest level built on
    /// the GPU each frame by vertex splitting in passes (LOD flag of Eq. 2 from the
    /// roughness of Eq. 3), T-junctions removed by triangle splitting; in core.
    Lee2011,
    /// Ripolles et al., GPU tessellation of terrain: four input triangles refined edge by
    /// edge by distance with Schmiade's seven patterns and coarsened family by family, one
    /// step a frame from the previous frame's tessellation (coherence); in core.
    Ripolles,
    /// A view-dependent right-triangulated irregular network built on the CPU from the
    /// full-resolution samples with exact per-vertex errors, kept conforming by nested
    /// errors and bounding spheres (Lindstrom & Pascucci 2002): the fewest-triangles
    /// yardstick.
    Rtin,
};

/// LodMethod::Ripolles's one parameter besides τ.
struct RipollesParameters {
    /// Each frame continues from the previous frame's tessellation with one step (§3.2); off:
    /// each frame starts from the input mesh and steps until nothing changes (Table 3's "no
    /// coherence exploitation").
    bool coherence = true;
};

struct LodMethodInfo {
    LodMethod method;
    std::string_view name;     ///< as --method takes it
    std::string_view summary;  ///< one line for --help and reports
    /// What the method promises about the measured error at threshold ε ("bounded": ≤ ε
    /// plus the rasterisation tolerance; "none": the threshold steers, it does not bound).
    bool boundsError;
    /// Draws skirts under its patch edges (Ulrich's, Yusov §5), which also cover the
    /// sub-pixel gaps a frame can show where triangles are seen edge-on or cut by the near
    /// plane. A method without them may show such pixels although its mesh is conforming.
    bool skirts;
    /// Holds the whole finest level in memory and streams nothing (the RTIN, Lee & Shin):
    /// the streaming stress test and the viewer refuse it.
    bool inCore;
    /// Draws globe pyramids too (the WGS84 cube-sphere); the others draw planar ones only,
    /// and a globe is refused with a message that says so (lodMethodSupports).
    bool globe;
    /// Its fragments go through terrain.frag, so it draws TerrainDebugView::PatchId: where its
    /// patches meet on screen, for the boundary-artefact measure (BoundaryArtefacts.h).
    bool patchIds;
};

/// Every method, the default first.
std::span<const LodMethodInfo> lodMethods();
const LodMethodInfo& lodMethodInfo(LodMethod method);
inline std::string_view lodMethodName(LodMethod method) { return lodMethodInfo(method).name; }

/// Whether `method` draws pyramids of `surface`; an Error naming the method and the
/// surface, and the methods that do, when it does not.
Status lodMethodSupports(LodMethod method, SurfaceKind surface);

/// A method by name; the error lists the names there are.
Result<LodMethod> parseLodMethod(std::string_view name);
/// A comma-separated list of names, or "all"; no repeats, at least one.
Result<std::vector<LodMethod>> parseLodMethods(std::string_view list);
/// "yusov2011, chunked-lod, …": for help texts.
std::string lodMethodNames();

}  // namespace terrain::runtime
