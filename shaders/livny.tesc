// Livny et al. 2007, "Seamless patches for GPU-based terrain rendering" (LodMethod::Livny2007),
// tessellation control: a patch is four triangular tiles cut by its diagonals (§3, "Patch
// Scheme", Fig. 3), each at the resolution of its boundary edge, chosen by Eq. 1: ε = ρ · l / d
// with d the camera's distance to the edge; resolution R1 = R_max / 2 for ε ≤ 1/2, R2 = R_max
// above (§3, "Level of Detail", two resolutions and a quadtree, the case Claim 1 proves
// crack-free). ρ = γ / (R_max · τ), so ε = γ · s / (τ · d), s the patch level's sample spacing
// (LodQuadtree's SplitRule::LivnyEdges, which split every patch with an ε > 1, uses the same
// d: livnyEdgeDistance in Aabb.h).
//
// Deviation, said where it is made: the paper draws cached meshes of tiles and stitching
// strips, instanced; here the tessellator generates each tile (triangle domain, its edge on
// the patch border at the tile's resolution, its two half-diagonals at the finer of the two
// tiles meeting there) and its transition rings take the strips' place. The patch border
// vertices — where neighbours meet — are the paper's: R segments of whole samples.
#include "Bindings.h"
#include "terrain_patches.glsl"
#include "surface_plane.glsl"

layout(vertices = 3) out;

uniform float u_innerScale;   // the tile's inner level: its resolution times this (1/√3:
                              // LivnyRenderer.cpp says why)

layout(location = 0) in vec2 i_sample[];
layout(location = 1) flat in int i_instance[];
layout(location = 2) flat in int i_primitive[];
layout(location = 0) out vec2 o_sample[];
layout(location = 1) flat out int o_instance[];
layout(location = 5) patch out int o_debugFactor;

// The patch's corners in its samples, GL's edge order: west, north, east, south edges run
// from kEdgeFrom to kEdgeTo (patch samples, Q = u_frame.tessellation.y · u_frame.tessellation.x).
vec2 corner(int i, float q) {
    return vec2((i == 1 || i == 2) ? q : 0.0, (i >= 2) ? q : 0.0);  // nw, ne, se, sw
}

// Edge e of the patch: its two corners (north-west first along it).
void edgeEnds(int e, float q, out vec2 a, out vec2 b) {
    // west: nw–sw, north: nw–ne, east: ne–se, south: sw–se
    a = e == 0 ? corner(0, q) : e == 1 ? corner(0, q) : e == 2 ? corner(1, q) : corner(3, q);
    b = e == 0 ? corner(3, q) : e == 1 ? corner(1, q) : e == 2 ? corner(2, q) : corner(2, q);
}

// Eq. 1's d for edge e: to the edge extruded over the DEM's heights (camera at the origin).
float edgeDistance(PatchInstance patch_, int e, float q) {
    vec2 a, b;
    edgeEnds(e, q, a, b);
    precise vec3 pa = terrainPositionM(patch_, a, 0.0);
    precise vec3 pb = terrainPositionM(patch_, b, 0.0);
    vec2 lo = min(pa.xy, pb.xy), hi = max(pa.xy, pb.xy);
    vec2 nearest = clamp(vec2(0.0), lo, hi);
    float below = u_frame.heightRange.x - u_frame.planeCamera.z, above = u_frame.heightRange.y - u_frame.planeCamera.z;
    float dz = max(max(below, -above), 0.0);
    return sqrt(dot(nearest, nearest) + dz * dz);
}

// Segments along edge e: R2 = Q when ε > 1/2, else R1 = Q / 2 (Claim 1's assignment).
float edgeResolution(PatchInstance patch_, int e, float q) {
    float spacingM = max(u_frame.planeSpacing.x, u_frame.planeSpacing.y) * patch_.placement0.z;
    float d = edgeDistance(patch_, e, q);
    float epsilon = d <= 0.0 ? 1.0e9 : u_frame.pixelsPerMetre.y * spacingM / (u_frame.screen.z * d);
    return epsilon > 0.5 ? q : 0.5 * q;
}

void main() {
    PatchInstance patch_ = u_instances[i_instance[0]];
    float q = float(u_frame.tessellation.y * u_frame.tessellation.x);
    int tile = i_primitive[0];  // 0 west, 1 north, 2 east, 3 south: the tile on that edge
    vec2 a, b;
    edgeEnds(tile, q, a, b);
    vec2 centre = vec2(0.5 * q);
    o_instance[gl_InvocationID] = i_instance[0];
    // Vertices: 0 and 1 the edge's ends, 2 the patch's centre.
    o_sample[gl_InvocationID] = gl_InvocationID == 0 ? a : gl_InvocationID == 1 ? b : centre;
    if (gl_InvocationID != 0) return;

    float own = edgeResolution(patch_, tile, q);
    // The tiles sharing this tile's half-diagonals: the previous and next edge's. A vertex
    // is a corner shared by two edges: a (first end) lies on the previous tile's edge for
    // west/north … take both neighbours by which corner they share.
    int atA = -1, atB = -1;
    for (int e = 0; e < 4; ++e) {
        if (e == tile) continue;
        vec2 ea, eb;
        edgeEnds(e, q, ea, eb);
        if (ea == a || eb == a) atA = e;
        if (ea == b || eb == b) atB = e;
    }
    float resA = max(own, edgeResolution(patch_, atA, q));
    float resB = max(own, edgeResolution(patch_, atB, q));
    // Triangle domain: outer[0] is the edge opposite vertex 0 (b–centre), [1] opposite
    // vertex 1 (a–centre), [2] opposite vertex 2 (a–b, the patch edge). A half-diagonal has
    // half the steps of the edge's grid.
    gl_TessLevelOuter[0] = 0.5 * resB;
    gl_TessLevelOuter[1] = 0.5 * resA;
    gl_TessLevelOuter[2] = own;
    gl_TessLevelInner[0] = max(1.0, own * u_innerScale);
    o_debugFactor = int(own);
}
