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

// Tile t's mesh over the box of half-width r around patch sample p: its height at p (x) and
// its mean slope over the box (y, z: per patch sample), the difference quotient across the box
// taken over its four corners. The box is cut to the tile's samples (its apron's included,
// −1 … N + 1).
vec3 boxSurface(vec4 t, vec2 p, float r) {
    float n = float(u_frame.tessellation.z);
    vec2 lo = max(p - r, (vec2(-1.0) - t.xy) / t.z);
    vec2 hi = min(p + r, (vec2(n + 1.0) - t.xy) / t.z);
    int layer = int(t.w);
    float h00 = heightBetween(tileTexel(t, lo), layer);
    float h10 = heightBetween(tileTexel(t, vec2(hi.x, lo.y)), layer);
    float h01 = heightBetween(tileTexel(t, vec2(lo.x, hi.y)), layer);
    float h11 = heightBetween(tileTexel(t, hi), layer);
    vec2 slope = vec2((h10 - h00) + (h11 - h01), (h01 - h00) + (h11 - h10)) / (2.0 * (hi - lo));
    return vec3(heightBetween(tileTexel(t, p), layer), slope);
}

// The ground under a pixel as its shading sees it: height and slopes filtered to the pixel's
// footprint, and how much they show over the mesh's own at the fragment.
struct FootprintSurface {
    float heightM;
    vec2 slope;    // mean over the footprint, per patch sample (x, y)
    float weight;  // 0 up to one sample of footprint, 1 from two: mix(mesh's, these, weight)
};

// The ground at patch sample p of `instance` for a pixel spanning `footprint` of its samples:
// beyond one sample, the height and mean slope over the footprint, taken from the pyramid's
// level whose samples are a half to a whole footprint apart, blended with the next coarser
// one by where the footprint lies between their spacings (trilinear, as a mip chain is
// sampled). The level is the footprint's in metres, whichever level's patch draws the pixel:
// two patches of different levels on either side of a boundary (and the reference's finest
// tiles) take a pixel's normal, tint and coast from the same data, and a box of at most two
// of that level's samples never reaches past its tile's apron, so it is not cut at the
// patch's edge. Only beyond TERRAIN_SHADING_ANCESTORS levels up (or above the pyramid's
// root) is the coarsest tile's box cut.
FootprintSurface footprintSurface(int instance, vec2 p, float footprint) {
    if (footprint <= 1.0) return FootprintSurface(0.0, vec2(0.0), 0.0);
    PatchInstance patch_ = u_instances[instance];
    float octave = log2(footprint);
    int k = min(int(floor(octave)), TERRAIN_SHADING_ANCESTORS);
    float r = 0.5 * footprint;
    vec3 ground = boxSurface(shadingTile(instance, patch_, k), p, r);
    if (k < TERRAIN_SHADING_ANCESTORS) {
        vec3 coarser = boxSurface(shadingTile(instance, patch_, k + 1), p, r);
        ground = mix(ground, coarser, clamp(octave - float(k), 0.0, 1.0));
    }
    return FootprintSurface(ground.x, ground.yz, smoothstep(1.0, 2.0, footprint));
}

// The shading normal: the mesh's own (`meshNormal`) blended into the footprint's; `up`: the
// surface's vertical.
vec3 footprintNormal(int instance, FootprintSurface ground, vec3 meshNormal, vec3 up) {
    if (ground.weight <= 0.0) return meshNormal;
    vec3 filtered = surfaceNormalFromSlopes(u_instances[instance], ground.slope, up);
    return normalize(mix(meshNormal, filtered, ground.weight));
}

// How much the ground changes across a pixel whose patch samples change by sampleDx and
// sampleDy from it to its neighbours, from its slope (per patch sample): where the coast is
// blended (terrainShade's coastWidthM).
float heightAcrossPixel(vec2 slope, vec2 sampleDx, vec2 sampleDy) {
    return abs(dot(slope, sampleDx)) + abs(dot(slope, sampleDy));
}

#endif  // TERRAIN_FOOTPRINT_GLSL
