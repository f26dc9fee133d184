// Lee & Shin 2011, triangle splitting (§2.4, Figs. 6–9). Built with LEE_FROM_LEAVES, the
// first pass: each leaf block becomes two triangles, or, when a neighbour block of its size
// was split, four triangles around its centre (Fig. 7), each of whose edges towards a split
// neighbour N is split at its T-vertex. Without it, one pass of the recursion (Fig. 8): a
// triangle ABC whose neighbour vertex N was split becomes ATC and TBC, their neighbour
// vertices the midpoints of AN and BN (the centres of N's children along the edge).
// A triangle whose neighbour is a finest block's quads cannot be split further and is drawn.
#include "lee_quadtree.glsl"

layout(local_size_x = 64) in;

struct PendingTriangle {
    ivec4 ab;  // A, B: the edge towards the neighbour
    ivec4 cn;  // C: the block's centre; N: the neighbour vertex
};

#ifdef LEE_FROM_LEAVES
layout(std430, binding = TERRAIN_BINDING_LEE_LEAVES) readonly buffer Leaves { ivec4 u_leaves[]; };
uniform uint u_leafCapacity;
#else
layout(std430, binding = TERRAIN_BINDING_LEE_INPUT) readonly buffer Pending {
    PendingTriangle u_pending[];
};
#endif
layout(std430, binding = TERRAIN_BINDING_LEE_OUTPUT) writeonly buffer StillPending {
    PendingTriangle u_stillPending[];
};
layout(std430, binding = TERRAIN_BINDING_LEE_TRIANGLES) writeonly buffer Triangles {
    ivec2 u_vertices[];  // 3 per triangle
};
layout(binding = TERRAIN_IMAGE_LEE_SPLIT_FLAGS, r8ui) uniform readonly uimage2D u_splitFlags;

uniform int u_pass;
uniform uint u_pendingCapacity;
uniform uint u_triangleCapacity;

bool wasSplit(ivec2 n) {
    if (any(lessThan(n, ivec2(0))) || any(greaterThan(n, ivec2(u_gridSide - 1)))) return false;
    return imageLoad(u_splitFlags, n).r != 0u;
}

void appendTriangle(ivec2 a, ivec2 b, ivec2 c) {
    uint slot = atomicAdd(c_triangles, 1u);
    if (slot < u_triangleCapacity) {
        u_vertices[3u * slot] = a;
        u_vertices[3u * slot + 1u] = b;
        u_vertices[3u * slot + 2u] = c;
    }
}

// Splits ABC at T, the midpoint of AB; the halves whose neighbours can still have split
// (their neighbour blocks have h ≥ 1) wait for the next pass.
void splitAtT(ivec2 a, ivec2 b, ivec2 c, ivec2 n) {
    ivec2 t = (a + b) / 2;
    int edge = max(abs(b.x - a.x), abs(b.y - a.y));  // = 2h of the neighbour block
    if (edge / 2 < 2) {
        appendTriangle(a, t, c);
        appendTriangle(t, b, c);
        return;
    }
    uint slot = atomicAdd(c_pending[u_pass + 1], 2u);
    if (slot + 1u < u_pendingCapacity) {
        u_stillPending[slot] = PendingTriangle(ivec4(a, t), ivec4(c, (a + n) / 2));
        u_stillPending[slot + 1u] = PendingTriangle(ivec4(t, b), ivec4(c, (b + n) / 2));
    }
}

void main() {
    uint i = gl_GlobalInvocationID.x;
#ifdef LEE_FROM_LEAVES
    if (i >= min(c_leaves, u_leafCapacity)) return;
    ivec4 leaf = u_leaves[i];
    ivec2 nw = leaf.xy;
    int size = leaf.z;
    ivec2 ne = nw + ivec2(size, 0), se = nw + ivec2(size), sw = nw + ivec2(0, size);
    if (size == 1) {  // a quad of a finest block drawn at full resolution
        appendTriangle(nw, ne, se);
        appendTriangle(nw, se, sw);
        return;
    }
    ivec2 c = nw + size / 2;
    const ivec2 corners[5] = ivec2[5](nw, ne, se, sw, nw);
    const ivec2 toNeighbour[4] = ivec2[4](ivec2(0, -size), ivec2(size, 0), ivec2(0, size),
                                          ivec2(-size, 0));  // north, east, south, west
    bool split[4];
    bool any = false;
    for (int e = 0; e < 4; ++e) {
        split[e] = wasSplit(c + toNeighbour[e]);
        any = any || split[e];
    }
    if (!any) {  // Fig. 6: the block as two triangles
        appendTriangle(nw, ne, se);
        appendTriangle(nw, se, sw);
        return;
    }
    for (int e = 0; e < 4; ++e) {  // Fig. 7: four triangles around the centre
        if (split[e]) {
            splitAtT(corners[e], corners[e + 1], c, c + toNeighbour[e]);
        } else {
            appendTriangle(corners[e], corners[e + 1], c);
        }
    }
#else
    if (i >= min(c_pending[u_pass], u_pendingCapacity)) return;
    PendingTriangle p = u_pending[i];
    if (wasSplit(p.cn.zw)) {
        splitAtT(p.ab.xy, p.ab.zw, p.cn.xy, p.cn.zw);
    } else {
        appendTriangle(p.ab.xy, p.ab.zw, p.cn.xy);
    }
#endif
}
