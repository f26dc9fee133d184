// Valdetaro et al. 2011, "LOD terrain rendering by local parallel processing on GPU"
// (LodMethod::Valdetaro2011), tessellation control: each primitive is a tile of the flat
// grid (ValdetaroTiles.h), tessellated on its own from five reference points — the middle
// of each edge and the tile's maximum (§3, Fig. 2) — with
//   T_max = g(HAM_max) = gain · √HAM_max                       (§5.1, Eq. 2, g the square root)
//   T_min from the screen error ε̂: the projected deviation L of the tile's highest sample
//         from the tile's bilinear surface halves with each level, L / 2^T ≤ ε̂, so the factor
//         2^T_min is L / ε̂                                    (§5.2, Eq. 3–4; see below)
//   T = T_max · d_max² / d² between d_max and d_min, T_max nearer, T_min further, d the
//       camera's distance to the reference point               (§5.3, Eq. 5a–c)
// An edge takes the larger T_max (and T_min) of the two tiles sharing it (§5.1), so both
// compute the same factor from the same inputs and the grid has no crack. As printed,
// Eq. 3–4 read ε̂ / h = 2^T, which gives negative levels for any error smaller than the
// deviation; the text ("the point moves a step towards the correct value at each factor …
// stops when the projected deviation is less than ε̂") is L / 2^T ≤ ε̂, used here.
// The method promises no error bound, and has no skirts: the paper has none.
// Tiles wholly beyond the DEM or outside the view frustum are discarded (the paper drew
// without culling, "which will not be the case in real applications").
#include "Bindings.h"
#include "terrain_patches.glsl"
#include "surface_plane.glsl"

layout(vertices = 4) out;

// One texel a tile of the grid (§6.2): HAM_max, h_max, the tile's bilinear surface under
// h_max, and where h_max lies (column + 128 · row from the tile's north-west sample).
layout(binding = TERRAIN_BINDING_VALDETARO_TILES) uniform sampler2D u_tiles;
uniform float u_hamGain;     // g(HAM) = gain · √HAM
uniform float u_dMaxM;       // d_max
uniform float u_maxFactor;   // 64, or the tile's quads if fewer (one quad a sample)

layout(location = 0) in vec2 i_sample[];
layout(location = 1) flat in int i_instance[];
layout(location = 2) flat in int i_primitive[];
layout(location = 0) out vec2 o_sample[];
layout(location = 1) flat out int o_instance[];
layout(location = 5) patch out int o_debugFactor;

float heightAt(PatchInstance patch_, ivec2 s) {
    return texelFetch(u_heights, ivec3(s + 1, patch_.layerLevel.x), 0).r;  // + the apron
}

vec2 pixelOf(vec3 p) {
    vec4 clip = u_frame.viewProjection * vec4(p, 1.0);
    return clip.xy / clip.w * 0.5 * u_frame.screen.xy;
}

// T_max and T_min of the grid's tile at `tileInPatch` (this patch's tiles, or a neighbour's
// across its border; clamped to the grid). Every input is the tile's texel and whole DEM
// samples, so the two tiles sharing an edge compute the same limits for it, bit for bit.
vec2 tileLimits(PatchInstance patch_, ivec2 tileInPatch) {
    ivec2 grid = textureSize(u_tiles, 0);
    ivec2 global = clamp(patch_.layerLevel.zw * u_frame.tessellation.x + tileInPatch, ivec2(0), grid - 1);
    vec4 t = texelFetch(u_tiles, global, 0);
    float tMax = clamp(u_hamGain * sqrt(t.x), 1.0, u_maxFactor);
    // The tile's highest sample and the tile's bilinear surface under it, projected.
    float packedAt = t.w;
    vec2 at = vec2(mod(packedAt, 128.0), floor(packedAt / 128.0));
    ivec2 tileOfPatch = global - patch_.layerLevel.zw * u_frame.tessellation.x;
    precise vec2 s = vec2(tileOfPatch * u_frame.tessellation.y) + at;
    precise vec3 top = terrainPositionM(patch_, s, t.y);
    precise vec3 under = terrainPositionM(patch_, s, t.z);
    vec4 a = u_frame.viewProjection * vec4(top, 1.0), b = u_frame.viewProjection * vec4(under, 1.0);
    float deviationPx =
        (a.w <= 0.0 || b.w <= 0.0) ? 1.0e9 : length(pixelOf(top) - pixelOf(under));
    float tMin = clamp(deviationPx / u_frame.screen.z, 1.0, u_maxFactor);
    return vec2(tMax, tMin);
}

// Eq. 5 at distance d for limits (T_max, T_min); T_min wins where it exceeds T_max.
float factorAt(float d, vec2 limits) {
    float t = d <= u_dMaxM ? limits.x : limits.x * (u_dMaxM * u_dMaxM) / (d * d);
    return clamp(t, limits.y, max(limits.x, limits.y));
}

void main() {
    o_sample[gl_InvocationID] = i_sample[gl_InvocationID];
    o_instance[gl_InvocationID] = i_instance[gl_InvocationID];
    if (gl_InvocationID != 0) return;
    PatchInstance patch_ = u_instances[i_instance[0]];
    int primitive = i_primitive[0];
    ivec2 tile = ivec2(primitive % u_frame.tessellation.x, primitive / u_frame.tessellation.x);
    ivec2 nw = tile * u_frame.tessellation.y;
    int half_ = u_frame.tessellation.y / 2;

    vec2 own = tileLimits(patch_, tile);
    // GL's outer order: west (u = 0), north (v = 0), east (u = 1), south (v = 1).
    const ivec2 kMid[4] = ivec2[](ivec2(0, 1), ivec2(1, 0), ivec2(2, 1), ivec2(1, 2));
    for (int i = 0; i < 4; ++i) {
        ivec2 mid = nw + kMid[i] * half_;
        vec2 other = tileLimits(patch_, tile + kEdgeNeighbour[i]);
        vec2 limits = max(own, other);
        precise vec3 p = terrainPositionM(patch_, vec2(mid), heightAt(patch_, mid));
        gl_TessLevelOuter[i] = factorAt(length(p), limits);
    }
    vec4 t = texelFetch(u_tiles, clamp(patch_.layerLevel.zw * u_frame.tessellation.x + tile, ivec2(0),
                                       textureSize(u_tiles, 0) - 1), 0);
    // T5 (§3): the tile's centre, at h_max.
    vec3 centre = terrainPositionM(patch_, vec2(nw) + vec2(half_), t.y);
    float inner = factorAt(length(centre), own);
    gl_TessLevelInner[0] = inner;
    gl_TessLevelInner[1] = inner;
    o_debugFactor = int(inner);

    vec3 lo = terrainPositionM(patch_, vec2(nw.x, nw.y + u_frame.tessellation.y), patch_.errors.z);
    vec3 hi = terrainPositionM(patch_, vec2(nw.x + u_frame.tessellation.y, nw.y), patch_.errors.w);
    bool beyond = any(greaterThan(terrainDemSample(patch_, vec2(nw)), u_frame.demExtent.zw));
    if (beyond || (u_frame.options.x != 0 && outsideFrustum(lo, hi))) {
        for (int i = 0; i < 4; ++i) gl_TessLevelOuter[i] = 0.0;
    }
}
