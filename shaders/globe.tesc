// Globe draw, tessellation control: the fine-grain LOD of Yusov & Shevtsov 2011, §5, on the
// ellipsoid. As terrain.tesc: one factor per block edge from Λ(d) = λ(d) + Err(P) of the
// blocks sharing it, the same for both blocks (same inputs, same `precise` operations), the
// interior the minimum of the edges, skirts along the edges. What differs is the bound on
// how many pixels a metre of error may cover: a block of a globe patch is curved and its
// "vertical" is the ellipsoid normal, so instead of the planar box it takes the sphere
// around the blocks (their corners at both heights, padded for the bulge between them): an
// error segment of length e anywhere in that sphere, at distance ≥ D from the camera, spans
// at most e · f · (1 + tan²(fovX/2) + tan²(fovY/2)) / D pixels, f the focal length in
// pixels (u_pxPerMAtUnitDistance is f times that bracket). Blocks and skirts whose sphere
// lies outside the view frustum are discarded.
#include "Bindings.h"
#include "globe_patches.glsl"

layout(vertices = 4) out;

layout(binding = TERRAIN_BINDING_BLOCK_ERRORS) uniform sampler2DArray u_blockErrors;
uniform float u_pxPerMAtUnitDistance;
uniform float u_nearM;
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
layout(location = 2) out float o_edgeFactor[];
layout(location = 3) out float o_edgeErrorM[];
layout(location = 4) patch out float o_skirtDropM;  // 0 for blocks
layout(location = 5) patch out int o_debugFactor;

// Λ(d) = λ(d) + Err(P), d = 1..4 (Yusov §5); a patch without a tile of its own (bare or
// virtual) has its λ in its instance.
vec4 blockErrorM(GlobeInstance patch_, ivec2 block) {
    int layer = patch_.layerLevelFace.x;
    bool ownTile = layer >= 0 && patch_.texelMap.w == 0.0;
    precise vec4 lambda = ownTile ? texelFetch(u_blockErrors, ivec3(block, layer), 0)
                                  : patch_.bareBlockErrors;
    precise vec4 total = lambda + patch_.errors.x;
    return total;
}

// The sphere (camera-relative centre, radius) around blocks first..last of the patch between
// its heights, reaching `belowM` further down.
vec4 blocksSphereM(GlobeInstance patch_, ivec2 first, ivec2 last, float belowM) {
    vec3 corners[8];
    vec3 centre = vec3(0.0);
    vec3 direction;
    for (int i = 0; i < 8; ++i) {
        ivec2 corner = ivec2((i & 1) != 0 ? last.x + 1 : first.x, (i & 2) != 0 ? last.y + 1 : first.y);
        float h = (i & 4) != 0 ? patch_.errors.w : patch_.errors.z - belowM;
        corners[i] = globePositionM(patch_, vec2(corner * u_blockQuads), h, direction);
        centre += corners[i];
    }
    centre *= 0.125;
    float radius = 0.0;
    for (int i = 0; i < 8; ++i) radius = max(radius, distance(centre, corners[i]));
    // The surface bulges past its corners by at most a chord's sagitta, diagonal² / 8ρ, ρ the
    // smallest radius of curvature (6,335 km), and float rounding by a few ulps of |centre|.
    float diagonal = distance(corners[0], corners[3]);
    radius += diagonal * diagonal / (8.0 * 6.3e6) + 1.0e-5 * length(centre) + 0.05;
    return vec4(centre, radius);
}

void edgeLod(GlobeInstance patch_, ivec2 block, int edge, out int d, out float errorM) {
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
        // Heights widened by Err(P): the surface an error's segment ends on may lie that far
        // beyond the patch's samples.
        vec4 sphere = blocksSphereM(patch_, first, last, patch_.errors.x);
        float distanceM = max(length(sphere.xyz) - sphere.w - patch_.errors.x, u_nearM);
        float pxPerM = u_pxPerMAtUnitDistance / distanceM;
        // Where Err(P) alone already shows more than ε (a virtual patch drawing a coarse
        // source near the camera, or the finest data seen closer than it was made for), no
        // tessellation can meet ε: the factors then hold only what the simplification adds,
        // λ(d), to ε, instead of tessellating everything to no avail.
        bool unreachable = patch_.errors.x * pxPerM >= u_errorPx;
        d = 0;
        for (int k = 1; k <= 4; ++k) {
            float errorK = unreachable ? edgeErrorM[k - 1] - patch_.errors.x : edgeErrorM[k - 1];
            if (errorK <= 0.0 || errorK * pxPerM < u_errorPx) d = k;
        }
    }
    errorM = d == 0 ? patch_.errors.x : edgeErrorM[d - 1];
}

bool blockOutsideFrustum(GlobeInstance patch_, ivec2 block, float dropM) {
    vec4 sphere = blocksSphereM(patch_, block, block, dropM);
    for (int i = 0; i < 5; ++i) {
        vec4 plane = u_frustumPlanes[i];
        if (dot(plane.xyz, sphere.xyz) + plane.w < -sphere.w) return true;
    }
    return false;
}

void main() {
    o_sample[gl_InvocationID] = i_sample[gl_InvocationID];
    o_instance[gl_InvocationID] = i_instance[gl_InvocationID];
    GlobeInstance patch_ = u_globe[i_instance[0]];
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
    int d;
    float errorM;
    edgeLod(patch_, block, edge, d, errorM);
    o_edgeFactor[gl_InvocationID] = float(max(1, u_blockQuads >> d));
    o_edgeErrorM[gl_InvocationID] = errorM;
    barrier();
    if (gl_InvocationID != 0) return;

    float inner;
    if (isSkirt) {
        float along = o_edgeFactor[0];
        gl_TessLevelOuter[0] = 1.0;
        gl_TessLevelOuter[1] = along;
        gl_TessLevelOuter[2] = 1.0;
        gl_TessLevelOuter[3] = along;
        gl_TessLevelInner[0] = along;
        gl_TessLevelInner[1] = 1.0;
        inner = along;
        o_skirtDropM = o_edgeErrorM[0] + patch_.errors.y;  // terrain.tesc says why
    } else {
        inner = min(min(o_edgeFactor[0], o_edgeFactor[1]), min(o_edgeFactor[2], o_edgeFactor[3]));
        for (int i = 0; i < 4; ++i) gl_TessLevelOuter[i] = o_edgeFactor[i];
        gl_TessLevelInner[0] = inner;
        gl_TessLevelInner[1] = inner;
        o_skirtDropM = 0.0;
    }
    o_debugFactor = int(inner);
    if (u_cullBlocks != 0 && blockOutsideFrustum(patch_, block, o_skirtDropM)) {
        for (int i = 0; i < 4; ++i) gl_TessLevelOuter[i] = 0.0;  // discards it (GL 4.5 §11.2.2)
    }
}
