// A patch's heights from its tile (one layer of the GPU pool's height array, with a one-sample
// apron), shared by the patch draws and the globe's reference draw, so all read a tile alike:
// a data patch's own samples; a virtual patch's ancestor's tile, bilinear between its samples
// (PatchInstance.texelMap); a native window's tile on its source's own triangles; layer < 0,
// no tile: the bare surface, height 0.
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

// The tile's height at a fractional tile sample on the source's own triangles, each cell split
// along its north-west–south-east diagonal (texel x east, y south), as io/build GeographicGrid
// interpolates a source and terrain.frag's fragmentNormal splits a cell: a native window
// (runtime/lod NativeWindowTree) draws these, so each of its flat triangles lies in the plane
// of one source triangle. A vertex two windows share reads the same texels the same way.
float heightInTriangles(vec2 texel, int layer) {
    vec2 base = floor(texel);
    vec2 f = texel - base;
    ivec2 t = ivec2(base);
    float h00 = heightAt(t, layer);
    float h11 = heightAt(t + ivec2(1, 1), layer);
    if (f.x >= f.y) {
        float h10 = heightAt(t + ivec2(1, 0), layer);
        return h00 + f.x * (h10 - h00) + f.y * (h11 - h10);
    }
    float h01 = heightAt(t + ivec2(0, 1), layer);
    return h00 + f.y * (h01 - h00) + f.x * (h11 - h01);
}

// The tile sample (apron included) under patch sample `s` of a record's texelMap: s + 1 for a
// data patch.
vec2 tileTexel(vec4 texelMap, vec2 s) { return texelMap.xy + s * texelMap.z + 1.0; }

// The height a patch draws at tile sample `texel`, by texelMap.w (`mode`): 0 the tile's own
// sample (a data patch), 1 bilinear between samples (a virtual patch), 2 on the source's
// triangles (a native window).
float tileHeight(vec2 texel, float mode, int layer) {
    if (mode == 0.0) return heightAt(ivec2(texel), layer);
    return mode == 2.0 ? heightInTriangles(texel, layer) : heightBetween(texel, layer);
}

#endif  // TERRAIN_HEIGHTS_GLSL
