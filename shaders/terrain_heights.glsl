// A patch's heights from its tile (one layer of the GPU pool's height array, with a one-sample
// apron), shared by the patch draws and the globe's reference draw, so all read a tile alike:
// a data patch's own samples; a virtual patch's ancestor's tile, bilinear between its samples
// (PatchInstance.texelMap); layer < 0, no tile: the bare surface, height 0.
#ifndef TERRAIN_HEIGHTS_GLSL
#define TERRAIN_HEIGHTS_GLSL

#include "Bindings.h"

layout(binding = TERRAIN_BINDING_HEIGHTS) uniform sampler2DArray u_heights;

float heightAt(ivec2 texel, int layer) {
    return layer >= 0 ? texelFetch(u_heights, ivec3(texel, layer), 0).r : 0.0;
}

// The tile's height at a fractional tile sample (apron included): bilinear, as a virtual
// patch draws its ancestor's tile between its samples.
float heightBetween(vec2 texel, int layer) {
    vec2 base = floor(texel);
    vec2 f = texel - base;
    ivec2 t = ivec2(base);
    float top = mix(heightAt(t, layer), heightAt(t + ivec2(1, 0), layer), f.x);
    float bottom = mix(heightAt(t + ivec2(0, 1), layer), heightAt(t + ivec2(1, 1), layer), f.x);
    return mix(top, bottom, f.y);
}

// The tile sample (apron included) under patch sample `s` of a record's texelMap: s + 1 for a
// data patch.
vec2 tileTexel(vec4 texelMap, vec2 s) { return texelMap.xy + s * texelMap.z + 1.0; }

// The height a patch draws at tile sample `texel`: between samples for a virtual patch.
float tileHeight(vec2 texel, bool between, int layer) {
    return between ? heightBetween(texel, layer) : heightAt(ivec2(texel), layer);
}

#endif  // TERRAIN_HEIGHTS_GLSL
