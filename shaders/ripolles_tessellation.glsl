// Ripolles et al., "Real-time tessellation of terrain on graphics hardware"
// (LodMethod::Ripolles): what the steps of the GPU tessellation share.
//
// The tessellation is a list of leaf triangles. Each triangle's edges are H = v0v1 (the
// hypotenuse of the right triangles of the input mesh), C1 = v1v2 and C2 = v2v0 (§3.1, Fig. 1);
// an edge needs refinement by the distance criterion the paper's experiments use (§3.1, §4:
// its length on screen at its midpoint's distance exceeds τ pixels), evaluated at its centre
// point, the same from both triangles that share it; the set of edges that need refinement
// selects one of Schmiade's seven patterns (a bit mask here: 1 H, 2 C1, 4 C2).
//
// The paper codes a triangle's ancestry in its id and patternInfo (Eq. 1–2) and recovers the
// parent from child 0 (Eq. 3–6). Here every refined triangle keeps a family record — the
// parent's vertices, its pattern (patternInfo's latest pattern), the family it belongs to and
// its place there (childType) — and each leaf its family and childType: the same
// information, stored where every child reaches it, plus a count of the family's children
// that are leaves, which coarsening needs and the paper does not say how to know.
#include "Bindings.h"
#include "terrain_frame.glsl"

struct Leaf {
    vec2 v0;
    vec2 v1;
    vec2 v2;
    int family;     // the family the triangle is a child of; −1 for the input mesh
    int childType;  // its place in the family (Eq. 1); the input triangle's index for −1
};

struct Family {
    vec2 p0;  // the parent triangle
    vec2 p1;
    vec2 p2;
    int parentFamily;     // the family the parent belongs to, −1 for an input triangle
    int parentChildType;  // the parent's place there
    int pattern;          // the edges refined (1 H, 2 C1, 4 C2)
    int leafChildren;     // children that are leaves now
    int allLeavesAtStart;  // 1: every child was a leaf when the step began (what it reads)
    int wants;  // 8 + the pattern the parent's edges select now, when it is not `pattern`
};

layout(std430, binding = TERRAIN_BINDING_RIPOLLES_COUNTERS) coherent buffer RipollesCounters {
    uint c_leaves;        // in the current tessellation
    uint c_nextLeaves;    // written by this step
    uint c_familyBump;    // family slots ever handed out (the array's used length)
    uint c_freeSlots;     // free family slots from earlier steps
    uint c_freeTaken;     // of those, taken by this step
    uint c_freedSlots;    // families freed by this step
    uint c_changes;       // triangles refined, families coarsened or re-patterned this step
    uint c_padding;
    uint c_mergeBase;     // after a step: where the slots it freed join the free stack
};

layout(std430, binding = TERRAIN_BINDING_RIPOLLES_FAMILIES) coherent buffer Families {
    Family u_families[];
};

// Schmiade's seven patterns: each child's vertices among v0, v1, v2 (0–2) and the midpoints
// of H, C1, C2 (3–5), child 0 first (the one that recovers the parent, §3.2).
const int kChildren[8] = int[8](1, 2, 2, 3, 2, 3, 3, 4);
const ivec3 kPattern[8][4] = ivec3[8][4](
    ivec3[4](ivec3(0, 1, 2), ivec3(0), ivec3(0), ivec3(0)),
    ivec3[4](ivec3(2, 0, 3), ivec3(1, 2, 3), ivec3(0), ivec3(0)),               // H
    ivec3[4](ivec3(0, 1, 4), ivec3(2, 0, 4), ivec3(0), ivec3(0)),               // C1
    ivec3[4](ivec3(2, 0, 3), ivec3(3, 1, 4), ivec3(2, 3, 4), ivec3(0)),         // H, C1
    ivec3[4](ivec3(0, 1, 5), ivec3(1, 2, 5), ivec3(0), ivec3(0)),               // C2
    ivec3[4](ivec3(1, 2, 3), ivec3(3, 2, 5), ivec3(0, 3, 5), ivec3(0)),         // H, C2
    ivec3[4](ivec3(0, 1, 4), ivec3(0, 4, 5), ivec3(5, 4, 2), ivec3(0)),         // C1, C2
    ivec3[4](ivec3(0, 3, 5), ivec3(3, 1, 4), ivec3(5, 4, 2), ivec3(4, 5, 3)));  // all

layout(binding = TERRAIN_BINDING_RIPOLLES_HEIGHTS) uniform sampler2D u_heightField;

uniform vec2 u_rasterSize;     // width, height in samples
uniform float u_thresholdPx;   // τ: the longest an edge may look, pixels

// The height at a DEM position (samples; clamped to the raster). Vertices are samples, so
// the filter only matters for the normals' neighbours beyond the raster.
float heightAt(vec2 s) {
    return texture(u_heightField, (clamp(s, vec2(0.0), u_rasterSize - 1.0) + 0.5) / u_rasterSize).r;
}

vec3 fromCamera(vec2 s) {
    precise vec2 metres = (s - planeAnchorSample() - u_frame.planeCamera.xy) * u_frame.planeSpacing.xy;
    precise float z = heightAt(s) - u_frame.planeCamera.z;
    return vec3(metres.x, -metres.y, z);
}

vec2 corner(int i, vec2 v0, vec2 v1, vec2 v2) {
    if (i == 0) return v0;
    if (i == 1) return v1;
    if (i == 2) return v2;
    if (i == 3) return 0.5 * (v0 + v1);
    if (i == 4) return 0.5 * (v1 + v2);
    return 0.5 * (v2 + v0);
}

// Whether edge pq needs refinement: the paper's distance criterion at its centre point, for
// an edge that can still be halved onto a sample (its extent even in x and y, at least 2:
// every vertex stays a DEM sample, and refinement ends — the patterns that split a leg alone
// would otherwise cut slivers without end), that touches the
// raster, and near enough to the view that a triangle it bounds may be seen (a sphere about
// its centre as large as the edge, plus the DEM's height range: the longest edge of a
// triangle sees all of it). Symmetric in p and q, so both triangles on an edge agree; every
// step is `precise`, so that each program that evaluates it (the step, the mark) decides
// alike — a family whose pattern one program disagreed with would never settle.
bool needsRefinement(vec2 p, vec2 q) {
    vec2 extent = abs(q - p);
    if (max(extent.x, extent.y) < 2.0 || any(notEqual(mod(extent, 2.0), vec2(0.0)))) return false;
    if (any(lessThan(max(p, q), vec2(0.0))) || any(greaterThan(min(p, q), u_rasterSize - 1.0)))
        return false;
    precise vec3 a = fromCamera(p);
    precise vec3 b = fromCamera(q);
    precise vec3 m = fromCamera(0.5 * (p + q));
    precise float lengthM = length(b - a);
    precise float radius = lengthM + (u_frame.heightRange.y - u_frame.heightRange.x);
    for (int i = 0; i < 5; ++i) {
        precise float side = dot(u_frame.frustumPlanes[i].xyz, m) + u_frame.frustumPlanes[i].w;
        if (side < -radius) return false;
    }
    precise float onScreen = lengthM * u_frame.pixelsPerMetre.y;
    precise float limit = u_thresholdPx * max(length(m), u_frame.screen.w);
    return onScreen > limit;
}

int refinementPattern(vec2 v0, vec2 v1, vec2 v2) {
    return (needsRefinement(v0, v1) ? 1 : 0) | (needsRefinement(v1, v2) ? 2 : 0) |
           (needsRefinement(v2, v0) ? 4 : 0);
}
