// Terrain draw, tessellation control: the fine-grain LOD of Yusov & Shevtsov 2011, §5
// ("Fine-Grain Level of Detail Selection"), one tessellation factor per block edge, with
// the edge error's projection bounded over the blocks sharing the edge rather than taken at
// its centre (EdgeTessellation.h says why).
// The CPU reference is runtime/lod/src/EdgeTessellation.cpp; TessellationFactorsTest compares
// the two.
//
// Invocation i of a block primitive decides the block's edge i (GL's outer order); the
// four invocations run the one edgeLod() below, so an edge shared by two blocks gets the
// same inputs through the same `precise` operations from both, and bit-identical factors:
// no crack inside a patch. Skirts decide their block's border edge the same way, so their
// top vertices are the patch's edge vertices.
//
// Blocks and skirts whose box lies outside the view frustum are discarded here (all outer
// levels 0): the coarse LOD culls whole patches, but a patch of a near view is mostly off
// screen, and Yusov's rule tessellates a near block finely wherever it lies. A discarded
// block leaves no crack on screen: its area is off screen, and its visible neighbours'
// edge factors do not depend on it being drawn.
//
// A patch the CPU marked as coarse cells (PatchInstance.coarseCells, runtime/lod
// CoarseCells.h) is drawn as a grid of cells of one quad each at factor 1: its blocks' edge
// rule is skipped, the cells' Λ is their error, and the primitives a cell covers are
// discarded.
#include "Bindings.h"
#include "terrain_patches.glsl"

layout(vertices = 4) out;

layout(binding = TERRAIN_BINDING_BLOCK_ERRORS) uniform sampler2DArray u_blockErrors;
uniform mat4 u_viewProjection;  // camera-relative metres to clip space
// The camera whose view decides the factors (TerrainStyle::lodCamera; by default the drawn
// one): its view-projection, relative to it, and the drawn camera's position minus its own.
uniform mat4 u_lodViewProjection;
uniform vec3 u_lodOffsetM;
uniform vec2 u_viewportPx;
uniform float u_errorPx;            // ε
uniform int u_fixedSimplification;  // −1: error-driven; else every edge uses this d
uniform int u_cullBlocks;           // 1: discard blocks and skirts outside the frustum
// The view frustum's planes (left, right, bottom, top, near) in camera-relative metres,
// normals inward: dot(n, p) + w ≥ 0 inside.
uniform vec4 u_frustumPlanes[5];

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

// Λ(d) = λ(d) + Err(P), d = 1..4 (Yusov §5, "Tessellation Blocks").
vec4 blockErrorM(PatchInstance patch_, ivec2 block) {
    precise vec4 lambda = texelFetch(u_blockErrors, ivec3(block, patch_.layerLevel.x), 0);
    precise vec4 total = lambda + patch_.errors.x;
    return total;
}

// An upper bound, in pixels per metre, on the on-screen length of any vertical segment in
// the box [lo, hi] (camera-relative metres); the derivation is verticalErrorPxPerM's
// (EdgeTessellation.h). It replaces Yusov's proj(e_c^(d),−, e_c^(d),+) at the edge centre
// (§5), which points of the block nearer the camera exceed.
float verticalErrorPxPerM(vec3 drawnLo, vec3 drawnHi) {
    vec3 lo = drawnLo + u_lodOffsetM, hi = drawnHi + u_lodOffsetM;  // relative to the LOD camera
    float nearM = u_lodViewProjection[3].z;  // Camera::projection: z_clip = near
    float depthMin = 3.0e38;
    vec2 ndcLo = vec2(3.0e38), ndcHi = vec2(-3.0e38);
    for (int i = 0; i < 8; ++i) {
        vec3 corner = vec3((i & 1) != 0 ? hi.x : lo.x, (i & 2) != 0 ? hi.y : lo.y,
                           (i & 4) != 0 ? hi.z : lo.z);
        vec4 clip = u_lodViewProjection * vec4(corner, 1.0);
        depthMin = min(depthMin, clip.w);
        vec2 ndc = clip.xy / clip.w;
        ndcLo = min(ndcLo, ndc);
        ndcHi = max(ndcHi, ndc);
    }
    if (!(depthMin > 0.0)) {  // the box reaches behind the camera: the screen bounds it
        ndcLo = vec2(-1.0);
        ndcHi = vec2(1.0);
    }
    ndcLo = clamp(ndcLo, -1.0, 1.0);
    ndcHi = clamp(ndcHi, -1.0, 1.0);
    vec4 a = u_lodViewProjection[2];  // the clip-space image of e_z
    vec2 halfViewport = 0.5 * u_viewportPx;
    float largest = 0.0;
    for (int i = 0; i < 4; ++i) {
        vec2 ndc = vec2((i & 1) != 0 ? ndcHi.x : ndcLo.x, (i & 2) != 0 ? ndcHi.y : ndcLo.y);
        largest = max(largest, length((a.xy - ndc * a.w) * halfViewport));
    }
    // A point in the frustum has |p| ≤ w · √(1 + tan²x + tan²y), and the rows of the
    // projection's x and y are the camera's right and up over tan x and tan y.
    vec3 rowX =
        vec3(u_lodViewProjection[0].x, u_lodViewProjection[1].x, u_lodViewProjection[2].x);
    vec3 rowY =
        vec3(u_lodViewProjection[0].y, u_lodViewProjection[1].y, u_lodViewProjection[2].y);
    float diagonal = sqrt(1.0 + 1.0 / dot(rowX, rowX) + 1.0 / dot(rowY, rowY));
    vec3 outside = max(max(lo, -hi), vec3(0.0));  // camera at the origin
    float depthOfDistance = length(outside) / diagonal;
    return largest / max(max(depthMin, depthOfDistance), nearM);
}

// The camera-relative box of blocks first..last (inclusive) of the patch: their footprint,
// and the patch's height range reaching `belowM` further down and `aboveM` further up.
void blocksBoxM(PatchInstance patch_, ivec2 first, ivec2 last, float belowM, float aboveM,
                out vec3 lo, out vec3 hi) {
    // The north-west corner at the patch's lowest height, the south-east one at its highest:
    // together they span the box. Rows run south, so the north-west corner has the larger y.
    vec3 nw = terrainPositionM(patch_, vec2(first * u_blockQuads), patch_.errors.z);
    vec3 se = terrainPositionM(patch_, vec2((last + 1) * u_blockQuads), patch_.errors.w);
    lo = vec3(nw.x, se.y, nw.z - belowM);
    hi = vec3(se.x, nw.y, se.z + aboveM);
}

// Edge `edge` of `block`: its simplification d and Λ_ec(d) (Err(P) at d = 0).
void edgeLod(PatchInstance patch_, ivec2 block, int edge, out int d, out float errorM) {
    // Λ_ec(d): the max over the blocks of this patch sharing the edge (Yusov §5), and the
    // box of those blocks, where the edge's d must hold. Both blocks compute the same box
    // from the same integers, so they agree on the edge bit for bit.
    vec4 edgeErrorM = blockErrorM(patch_, block);
    ivec2 other = block + kEdgeNeighbour[edge];
    ivec2 first = block, last = block;
    if (all(greaterThanEqual(other, ivec2(0))) && all(lessThan(other, ivec2(u_blocksPerSide)))) {
        edgeErrorM = max(edgeErrorM, blockErrorM(patch_, other));
        first = min(block, other);
        last = max(block, other);
    }
    if (u_fixedSimplification >= 0) {
        d = u_fixedSimplification;
    } else {
        // Heights widened by Err(P): the full-resolution surface, where an error's
        // segment ends, may lie that far beyond the patch's samples.
        vec3 lo, hi;
        blocksBoxM(patch_, first, last, patch_.errors.x, patch_.errors.x, lo, hi);
        float pxPerM = verticalErrorPxPerM(lo, hi);
        // d = argmax_d Λ_ec(d) · pxPerM < ε; 0 (full resolution) when no d qualifies. No
        // error is nothing to see, wherever the box lies.
        d = 0;
        for (int k = 1; k <= 4; ++k) {
            float errorK = edgeErrorM[k - 1];
            if (errorK <= 0.0 || errorK * pxPerM < u_errorPx) d = k;
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
// coarser edge to a finer inner mesh is one λ does not bound.
float blockInnerFactor(PatchInstance patch_, ivec2 block, float coarsestEdgeFactor) {
    if (u_fixedSimplification >= 0) return coarsestEdgeFactor;
    vec4 ownErrorM = blockErrorM(patch_, block);
    vec3 lo, hi;
    blocksBoxM(patch_, block, block, patch_.errors.x, patch_.errors.x, lo, hi);
    float pxPerM = verticalErrorPxPerM(lo, hi);
    float inner = coarsestEdgeFactor;
    for (int k = 1; k <= 4; ++k) {
        float factor = float(max(1, u_blockQuads >> k));
        float errorK = ownErrorM[k - 1];
        if (factor < inner && (errorK <= 0.0 || errorK * pxPerM < u_errorPx)) inner = factor;
    }
    return inner;
}

// Whether the box [lo, hi] (camera-relative metres) lies entirely outside one plane of the
// frustum. Conservative: the box must clear the plane by a margin that covers float
// rounding of the box and planes, so nothing visible is ever discarded.
bool outsideFrustum(vec3 lo, vec3 hi) {
    for (int i = 0; i < 5; ++i) {
        vec4 plane = u_frustumPlanes[i];
        vec3 far = mix(lo, hi, greaterThanEqual(plane.xyz, vec3(0.0)));  // furthest along n
        float marginM = 0.05 + 1.0e-5 * (abs(far.x) + abs(far.y) + abs(far.z));
        if (dot(plane.xyz, far) + plane.w < -marginM) return true;
    }
    return false;
}

// The camera-relative box of blocks first..last of the patch, from the patch's height range,
// reaching `dropM` further down (a skirt's drop; 0 for blocks themselves).
bool blocksOutsideFrustum(PatchInstance patch_, ivec2 first, ivec2 last, float dropM) {
    vec3 lo, hi;
    blocksBoxM(patch_, first, last, dropM, 0.0, lo, hi);
    return outsideFrustum(lo, hi);
}

// Coarse cells (runtime/lod CoarseCells.h): the CPU found the whole patch within ε drawn as
// cells of cellBlocks × cellBlocks blocks, one quad each at factor 1. The primitive of the
// cell's north-west block draws the cell, and a skirt whose block starts a cell's side hangs
// from that side; the others are discarded. A block or skirt corner is (block + offset) · B
// with offset in {0, 1}²; the cell's is (cell + offset) · cellBlocks · B (exact integers).
vec2 coarseCellCorner(vec2 blockCorner, ivec2 block, int cellBlocks) {
    vec2 offset = blockCorner / float(u_blockQuads) - vec2(block);
    return (vec2(block / cellBlocks) + offset) * float(cellBlocks * u_blockQuads);
}

bool drawsCoarseCell(ivec2 block, bool isSkirt, int edge, int cellBlocks) {
    if (isSkirt) return ((edge & 1) == 0 ? block.y : block.x) % cellBlocks == 0;  // W, E: along y
    return all(equal(block % cellBlocks, ivec2(0)));
}

// Whether `block` lies wholly beyond the DEM's extent (in a patch overhanging its right
// or bottom edge): it would draw only clamped copies of the edge.
bool blockBeyondDem(PatchInstance patch_, ivec2 block) {
    vec2 first = terrainDemSample(patch_, vec2(block * u_blockQuads));
    return any(greaterThan(first, u_demLastSample));
}

void main() {
    o_instance[gl_InvocationID] = i_instance[gl_InvocationID];
    PatchInstance patch_ = u_instances[i_instance[0]];
    int primitive = i_primitive[0];
    int blocks = u_blocksPerSide * u_blocksPerSide;
    bool isSkirt = primitive >= blocks;
    ivec2 block;
    int edge;
    if (isSkirt) {
        int skirt = primitive - blocks;
        edge = skirt / u_blocksPerSide;
        block = terrainSkirtBlock(edge, skirt % u_blocksPerSide);
    } else {
        block = ivec2(primitive % u_blocksPerSide, primitive / u_blocksPerSide);
        edge = gl_InvocationID;
    }
    int cellQuads = u_fixedSimplification < 0 ? int(patch_.coarseCells.x) : 0;
    int cellBlocks = max(1, cellQuads / u_blockQuads);
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
        o_edgeFactor[gl_InvocationID] = float(max(1, u_blockQuads >> d));
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
    bool culled = !merged && (blockBeyondDem(patch_, first) ||
                              (u_cullBlocks != 0 &&
                               blocksOutsideFrustum(patch_, first, first + (cellBlocks - 1),
                                                    o_skirtDropM)));
#ifdef TERRAIN_DEBUG_TESS_FACTORS
    int record = i_instance[0] * (blocks + 4 * u_blocksPerSide) + primitive;
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
