// The shading normal filtered to a pixel's footprint, for the patch draws (terrain.frag) and
// the reference draws (reference.frag), so both filter alike. Where a pixel spans more than
// one of a patch's samples, its normal is that of the mean slope over the pixel's footprint:
// the difference quotient of the mesh's heights across the footprint (the mean of a
// derivative over an interval is the difference of its ends over the interval's length),
// taken over the box's four corners, so detail finer than a pixel does not alias into a moiré
// or into pixels that stand out from their neighbours. It blends in from the mesh's own normal
// between one and two samples of footprint. Needs terrain_surface.glsl
// (surfaceNormalFromSlopes) and the patch records (terrain_patches.glsl).
#ifndef TERRAIN_FOOTPRINT_GLSL
#define TERRAIN_FOOTPRINT_GLSL

#include "terrain_heights.glsl"

// How many of the patch's samples a pixel spans at patch sample p: call it where control flow
// is uniform (before any discard), as screen-space derivatives need.
float sampleFootprint(vec2 p) { return max(length(dFdx(p)), length(dFdy(p))); }

// The tiles above a patch's own, for footprints wider than its samples (runtime/draw
// ShadingTiles.h): record instance · TERRAIN_SHADING_ANCESTORS + k − 1 is the tile k levels up,
// its sample xy + s · z under the patch's sample s, its layer w (−1: none, the bare surface).
layout(std430, binding = TERRAIN_BINDING_SHADING_TILES) readonly buffer ShadingTiles {
    vec4 u_shadingTiles[];
};

// The tile k levels above the patch's own (k = 0: its own), as a texelMap with the layer in w.
vec4 shadingTile(int instance, PatchInstance patch_, int k) {
    if (k == 0) return vec4(patch_.texelMap.xyz, float(patch_.layerLevel.x));
    return u_shadingTiles[instance * TERRAIN_SHADING_ANCESTORS + k - 1];
}

// The mean slope (per patch sample, x and y) of tile t's mesh over the box of half-width r
// around patch sample p: the difference quotient across the box, taken over its four corners.
// The box is cut to the tile's samples (its apron's included, −1 … N + 1).
vec2 boxSlope(vec4 t, vec2 p, float r) {
    float n = float(u_frame.tessellation.z);
    vec2 lo = max(p - r, (vec2(-1.0) - t.xy) / t.z);
    vec2 hi = min(p + r, (vec2(n + 1.0) - t.xy) / t.z);
    int layer = int(t.w);
    float h00 = heightBetween(tileTexel(t, lo), layer);
    float h10 = heightBetween(tileTexel(t, vec2(hi.x, lo.y)), layer);
    float h01 = heightBetween(tileTexel(t, vec2(lo.x, hi.y)), layer);
    float h11 = heightBetween(tileTexel(t, hi), layer);
    return vec2((h10 - h00) + (h11 - h01), (h01 - h00) + (h11 - h10)) / (2.0 * (hi - lo));
}

// The normal at patch sample p of `instance` (a pixel spanning `footprint` of its samples):
// `meshNormal`, the mesh's own, up to one sample of footprint; beyond, that of the mean slope
// over the footprint, taken from the pyramid's level whose samples are a half to a whole
// footprint apart, blended with the next coarser one by where the footprint lies between
// their spacings (trilinear, as a mip chain is sampled). The level is the footprint's in
// metres, whichever level's patch draws the pixel: two patches of different levels on either
// side of a boundary (and the reference's finest tiles) take the same pixel's normal from the
// same data, and a box of at most two of that level's samples never reaches past its tile's
// apron, so it is not cut at the patch's edge. Only beyond TERRAIN_SHADING_ANCESTORS levels up
// (or above the pyramid's root) is the coarsest tile's box cut. `up`: the surface's vertical.
vec3 footprintNormal(int instance, vec2 p, float footprint, vec3 meshNormal, vec3 up) {
    if (footprint <= 1.0) return meshNormal;
    PatchInstance patch_ = u_instances[instance];
    float octave = log2(footprint);
    int k = min(int(floor(octave)), TERRAIN_SHADING_ANCESTORS);
    float r = 0.5 * footprint;
    vec2 slope = boxSlope(shadingTile(instance, patch_, k), p, r);
    if (k < TERRAIN_SHADING_ANCESTORS) {
        vec2 coarser = boxSlope(shadingTile(instance, patch_, k + 1), p, r);
        slope = mix(slope, coarser, clamp(octave - float(k), 0.0, 1.0));
    }
    vec3 filtered = surfaceNormalFromSlopes(patch_, slope, up);
    return normalize(mix(meshNormal, filtered, smoothstep(1.0, 2.0, footprint)));
}

#endif  // TERRAIN_FOOTPRINT_GLSL
