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

// The mesh's height at patch sample p (fractional; the apron's samples reach −1 and N + 1).
float patchMeshHeight(PatchInstance patch_, vec2 p) {
    return heightBetween(tileTexel(patch_.texelMap, p), patch_.layerLevel.x);
}

// `meshNormal`: the mesh's own normal at p; `up`: the surface's vertical there. The box is cut
// to the tile's samples (its apron's included, −1 … N + 1). (Sliding it inwards whole instead
// measured worse: Rainier's shading seam 1.57–2.28 levels against 1.46–1.82 cut.)
vec3 footprintNormal(PatchInstance patch_, vec2 p, float footprint, vec3 meshNormal, vec3 up) {
    if (footprint <= 1.0) return meshNormal;
    float n = float(u_frame.tessellation.z);
    vec2 lo = max(p - 0.5 * footprint, vec2(-1.0));
    vec2 hi = min(p + 0.5 * footprint, vec2(n + 1.0));
    float h00 = patchMeshHeight(patch_, lo), h10 = patchMeshHeight(patch_, vec2(hi.x, lo.y));
    float h01 = patchMeshHeight(patch_, vec2(lo.x, hi.y)), h11 = patchMeshHeight(patch_, hi);
    vec2 slope = vec2((h10 - h00) + (h11 - h01), (h01 - h00) + (h11 - h10)) / (2.0 * (hi - lo));
    vec3 filtered = surfaceNormalFromSlopes(patch_, slope, up);
    return normalize(mix(meshNormal, filtered, smoothstep(1.0, 2.0, footprint)));
}

#endif  // TERRAIN_FOOTPRINT_GLSL
