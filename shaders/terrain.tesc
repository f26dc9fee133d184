// Terrain draw, tessellation control, on either surface: the fine-grain LOD of Yusov &
// Shevtsov 2011, §5 ("Fine-Grain Level of Detail Selection"), one tessellation factor per
// block edge, with the edge error's projection bounded over the blocks sharing the edge rather
// than taken at its centre (EdgeTessellation.h says why). How many pixels a metre of error may
// cover over a set of blocks, and whether they lie in the frustum, is the surface's
// (surface_plane.glsl: their box; surface_globe.glsl: the sphere around them, the blocks being
// curved). The CPU reference is runtime/lod/src/EdgeTessellation.cpp (the plane's);
// TessellationFactorsTest compares the two.
//
// Invocation i of a block primitive decides the block's edge i (GL's outer order); the
// four invocations run the one edgeLod() below, so an edge shared by two blocks gets the
// same inputs through the same `precise` operations from both, and bit-identical factors:
// no crack inside a patch. Skirts decide their block's border edge the same way, so their
// top vertices are the patch's edge vertices.
//
// Blocks and skirts outside the view frustum are discarded here (all outer levels 0): the
// coarse LOD culls whole patches, but a patch of a near view is mostly off screen, and
// Yusov's rule tessellates a near block finely wherever it lies. A discarded block leaves no
// crack on screen: its area is off screen, and its visible neighbours' edge factors do not
// depend on it being drawn.
//
// A patch the CPU marked as coarse cells (PatchInstance.coarseCells, runtime/lod
// CoarseCells.h) is drawn as a grid of cells of one quad each at factor 1: its blocks' edge
// rule is skipped, the cells' Λ is their error, and the primitives a cell covers are
// discarded. Only the plane's draw chooses coarse cells and a block's own inner level
// (blockInnerFactor) so far; the globe's keeps every block and the minimum of its edges.
#include "Bindings.h"
#include "terrain_patches.glsl"
#include "terrain_surface.glsl"

layout(vertices = 4) out;

layout(binding = TERRAIN_BINDING_BLOCK_ERRORS) uniform sampler2DArray u_blockErrors;

layout(location = 0) in vec2 i_sample[];
layout(location = 1) flat in int i_instance[];
layout(location = 2) flat in int i_primitive[];
layout(location = 0) out vec2 o_sample[];
layout(location = 1) flat out int o_instance[];
// Scratch between the invocations: edge i's factor and Λ_ec at its d.
layout(location = 2) out float o_edgeFactor[];
layout(location = 3) out float o_edgeErrorM[];
layout(location = 4) patch out float o_skirtDropM;  // 0 for blocks
layout(location = 5) patch out int o_debugFactor;   // block: inner factor; skirt: along the edge

#ifdef TERRAIN_DEBUG_TESS_FACTORS
struct TessFactorRecord {
    ivec4 outer;  // before culling
    ivec2 inner;
    int flags;  // kRecordSkirt | kRecordCulled | kRecordMerged
    float skirtDropM;
};
const int kRecordSkirt = 1;   // RecordedTessFactors::kSkirt
const int kRecordCulled = 2;  // RecordedTessFactors::kCulled
const int kRecordMerged = 4;  // RecordedTessFactors::kMerged
layout(std430, binding = TERRAIN_BINDING_DEBUG_TESS_FACTORS) writeonly buffer TessFactors {
    TessFactorRecord u_tessFactors[];  // (instance · (K² + 4K) + primitive)
};
#endif

// Λ(d) = λ(d) + Err(P), d = 1..4 (Yusov §5, "Tessellation Blocks"); a patch without a tile of
// its own (bare or virtual) has its λ in its instance. A tile's own λ(d) is added what its
// instance holds: 0 for a face patch (its tile's λ has the ellipsoid's bulge), the bulge over
// blocks simplified by 2^d for a native tile (a planar pyramid's λ has none).
vec4 blockErrorM(PatchInstance patch_, ivec2 block) {
    int layer = patch_.layerLevel.x;
    bool ownTile = layer >= 0 && patch_.texelMap.w == 0.0;
    precise vec4 lambda = ownTile ? texelFetch(u_blockErrors, ivec3(block, layer), 0) +
                                        patch_.bareBlockErrors
                                  : patch_.bareBlockErrors;
    precise vec4 total = lambda + patch_.errors.x;
    return total;
}

// Edge `edge` of `block`: its simplification d and Λ_ec(d) (Err(P) at d = 0).
void edgeLod(PatchInstance patch_, ivec2 block, int edge, out int d, out float errorM) {
    // Λ_ec(d): the max over the blocks of this patch sharing the edge (Yusov §5), and the
    // blocks where the edge's d must hold. Both blocks compute the same bound from the same
    // integers, so they agree on the edge bit for bit.
    int blocksPerSide = u_frame.tessellation.x;
    vec4 edgeErrorM = blockErrorM(patch_, block);
    ivec2 other = block + kEdgeNeighbour[edge];
    ivec2 first = block, last = block;
    if (all(greaterThanEqual(other, ivec2(0))) && all(lessThan(other, ivec2(blocksPerSide)))) {
        edgeErrorM = max(edgeErrorM, blockErrorM(patch_, other));
        first = min(block, other);
        last = max(block, other);
    }
    if (u_frame.tessellation.w >= 0) {
        d = u_frame.tessellation.w;
    } else {
        // Heights widened by Err(P): the full-resolution surface, where an error's
        // segment ends, may lie that far beyond the patch's samples.
        float pxPerM = blocksPxPerM(patch_, first, last, patch_.errors.x);
        float errorPx = u_frame.screen.z;
        // Where Err(P) alone already shows more than ε (a virtual patch drawing a coarse
        // source near the camera, or the finest data seen closer than it was made for), no
        // tessellation can meet ε: the factors then hold only what the simplification adds,
        // λ(d), to ε, instead of tessellating everything to no avail. Only where the coarse
        // stage takes the whole ε (the globe); the plane's leaves the fine stage room.
        bool unreachable = kCoarseStageTakesWholeEpsilon && patch_.errors.x * pxPerM >= errorPx;
        // d = argmax_d Λ_ec(d) · pxPerM < ε; 0 (full resolution) when no d qualifies. No
        // error is nothing to see, wherever the blocks lie.
        d = 0;
        for (int k = 1; k <= 4; ++k) {
            float errorK = unreachable ? edgeErrorM[k - 1] - patch_.errors.x : edgeErrorM[k - 1];
            if (errorK <= 0.0 || errorK * pxPerM < errorPx) d = k;
        }
    }
    errorM = d == 0 ? patch_.errors.x : edgeErrorM[d - 1];
}

// The block's inner factor. Yusov §5 takes the minimum of its edge factors, the coarsest
// edge's d. But an edge's d holds for the box of both blocks sharing it, with the larger of
// their errors, and the inner mesh touches no neighbour: the block may go coarser on its
// own, to the largest d whose own Λ(d), projected over its own box, stays below ε. Λ(d)
// bounds the regular mesh at d and its strips to edges of every finer factor
// (io::transitionErrors), and every edge is at least as fine as that inner level, so the
// bound holds for the whole block. Never finer than the coarsest edge: a strip from a
// coarser edge to a finer inner mesh is one λ does not bound. The plane's draw only so far.
float blockInnerFactor(PatchInstance patch_, ivec2 block, float coarsestEdgeFactor) {
#ifdef TERRAIN_SURFACE_GLOBE
    return coarsestEdgeFactor;
#else
    if (u_frame.tessellation.w >= 0) return coarsestEdgeFactor;
    int blockQuads = u_frame.tessellation.y;
    vec4 ownErrorM = blockErrorM(patch_, block);
    float pxPerM = blocksPxPerM(patch_, block, block, patch_.errors.x);
    float inner = coarsestEdgeFactor;
    for (int k = 1; k <= 4; ++k) {
        float factor = float(max(1, blockQuads >> k));
        float errorK = ownErrorM[k - 1];
        if (factor < inner && (errorK <= 0.0 || errorK * pxPerM < u_frame.screen.z))
            inner = factor;
    }
    return inner;
#endif
}

// Coarse cells (runtime/lod CoarseCells.h): the CPU found the whole patch within ε drawn as
// cells of cellBlocks × cellBlocks blocks, one quad each at factor 1. The primitive of the
// cell's north-west block draws the cell, and a skirt whose block starts a cell's side hangs
// from that side; the others are discarded. A block or skirt corner is (block + offset) · B
// with offset in {0, 1}²; the cell's is (cell + offset) · cellBlocks · B (exact integers).
vec2 coarseCellCorner(vec2 blockCorner, ivec2 block, int cellBlocks) {
    int blockQuads = u_frame.tessellation.y;
    vec2 offset = blockCorner / float(blockQuads) - vec2(block);
    return (vec2(block / cellBlocks) + offset) * float(cellBlocks * blockQuads);
}

bool drawsCoarseCell(ivec2 block, bool isSkirt, int edge, int cellBlocks) {
    if (isSkirt) return ((edge & 1) == 0 ? block.y : block.x) % cellBlocks == 0;  // W, E: along y
    return all(equal(block % cellBlocks, ivec2(0)));
}

void main() {
    o_instance[gl_InvocationID] = i_instance[gl_InvocationID];
    PatchInstance patch_ = u_instances[i_instance[0]];
    int blocksPerSide = u_frame.tessellation.x;
    int blockQuads = u_frame.tessellation.y;
    int primitive = i_primitive[0];
    int blocks = blocksPerSide * blocksPerSide;
    bool isSkirt = primitive >= blocks;
    ivec2 block;
    int edge;
    if (isSkirt) {
        int skirt = primitive - blocks;
        edge = skirt / blocksPerSide;
        block = terrainSkirtBlock(edge, skirt % blocksPerSide);
    } else {
        block = ivec2(primitive % blocksPerSide, primitive / blocksPerSide);
        edge = gl_InvocationID;
    }
    int cellQuads = u_frame.tessellation.w < 0 ? int(patch_.coarseCells.x) : 0;
    int cellBlocks = max(1, cellQuads / blockQuads);
    if (cellQuads > 0) {
        o_sample[gl_InvocationID] = coarseCellCorner(i_sample[gl_InvocationID], block, cellBlocks);
        o_edgeFactor[gl_InvocationID] = 1.0;
        o_edgeErrorM[gl_InvocationID] = patch_.coarseCells.y;
    } else {
        o_sample[gl_InvocationID] = i_sample[gl_InvocationID];
        int d;
        float errorM;
        edgeLod(patch_, block, edge, d, errorM);
        // Powers of two dividing the block's quads: every vertex lands on a sample. A
        // simplification coarser than the block keeps its corners (factor 1).
        o_edgeFactor[gl_InvocationID] = float(max(1, blockQuads >> d));
        o_edgeErrorM[gl_InvocationID] = errorM;
    }
    barrier();
    if (gl_InvocationID != 0) return;

    float inner;
    if (isSkirt) {
        // Along the edge (u) the block edge's factor, so the skirt's top vertices are the
        // patch's edge vertices; across (v) one segment.
        float along = o_edgeFactor[0];
        gl_TessLevelOuter[0] = 1.0;
        gl_TessLevelOuter[1] = along;
        gl_TessLevelOuter[2] = 1.0;
        gl_TessLevelOuter[3] = along;
        gl_TessLevelInner[0] = along;
        gl_TessLevelInner[1] = 1.0;
        inner = along;
        // Why this depth hides every crack (Ulrich's skirts, Yusov §5): along the edge
        // this patch's drawn surface is within Λ_A = Λ_ec(d) of the full-resolution
        // surface and its neighbour's within its own Λ_B, so the gap between them is at
        // most Λ_A + Λ_B. Λ_A is known here; the CPU bounds any neighbour's Λ_B by the
        // instance's skirt depth (assignSkirtDepths, and the coarse cells' Λ).
        o_skirtDropM = o_edgeErrorM[0] + patch_.errors.y;
    } else if (cellQuads > 0) {
        for (int i = 0; i < 4; ++i) gl_TessLevelOuter[i] = 1.0;
        inner = 1.0;
        gl_TessLevelInner[0] = inner;
        gl_TessLevelInner[1] = inner;
        o_skirtDropM = 0.0;
    } else {
        inner = blockInnerFactor(patch_, block,
                                 min(min(o_edgeFactor[0], o_edgeFactor[1]),
                                     min(o_edgeFactor[2], o_edgeFactor[3])));
        for (int i = 0; i < 4; ++i) gl_TessLevelOuter[i] = o_edgeFactor[i];
        gl_TessLevelInner[0] = inner;
        gl_TessLevelInner[1] = inner;
        o_skirtDropM = 0.0;
    }
    o_debugFactor = int(inner);
    bool merged = cellQuads > 0 && !drawsCoarseCell(block, isSkirt, edge, cellBlocks);
    ivec2 first = cellQuads > 0 ? (block / cellBlocks) * cellBlocks : block;
    bool culled = !merged && (blockBeyondExtent(patch_, first) ||
                              (isSkirt && skirtAlongSurfaceEdge(patch_, block, edge)) ||
                              (u_frame.options.x != 0 &&
                               blocksOutsideFrustum(patch_, first, first + (cellBlocks - 1),
                                                    o_skirtDropM)));
#ifdef TERRAIN_DEBUG_TESS_FACTORS
    int record = i_instance[0] * (blocks + 4 * blocksPerSide) + primitive;
    u_tessFactors[record].outer =
        merged ? ivec4(0)
               : ivec4(gl_TessLevelOuter[0], gl_TessLevelOuter[1], gl_TessLevelOuter[2],
                       gl_TessLevelOuter[3]);
    u_tessFactors[record].inner =
        merged ? ivec2(0) : ivec2(gl_TessLevelInner[0], gl_TessLevelInner[1]);
    u_tessFactors[record].flags = (isSkirt ? kRecordSkirt : 0) | (culled ? kRecordCulled : 0) |
                                  (merged ? kRecordMerged : 0);
    u_tessFactors[record].skirtDropM = o_skirtDropM;
#endif
    if (culled || merged) {
        // An outer level of 0 discards the primitive (GL 4.5 §11.2.2).
        for (int i = 0; i < 4; ++i) gl_TessLevelOuter[i] = 0.0;
    }
}
