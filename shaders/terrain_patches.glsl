// The patch draws' per-instance records (PatchInstanceLayout.h, one per drawn patch, std430; the
// renderers write them through runtime/draw PatchInstance.h), and the primitives of an
// instance (terrain_primitives.glsl). Where a record's patch lies is its surface's:
// surface_plane.glsl, surface_globe.glsl.
#ifndef TERRAIN_PATCHES_GLSL
#define TERRAIN_PATCHES_GLSL

#include "Bindings.h"
#include "PatchInstanceLayout.h"
#include "terrain_primitives.glsl"

struct PatchInstance {
    TERRAIN_PATCH_INSTANCE_MEMBERS(TERRAIN_GLSL_VEC4, TERRAIN_GLSL_IVEC4)
};

layout(std430, binding = TERRAIN_BINDING_PATCH_INSTANCES) readonly buffer PatchInstances {
    PatchInstance u_instances[];
};

layout(binding = TERRAIN_BINDING_BLOCK_RANGES) uniform sampler2DArray u_blockRanges;

// The heights blocks first..last of the patch span (lowest, highest): their own (the GPU
// pool's blockRanges) where the patch has a tile of its own and they are one block or an
// edge's two, else the patch's whole range (a coarse cell's blocks; a bare or virtual patch,
// whose heights are not its tile's). The CPU model (runtime/lod EdgeTessellation.cpp) takes
// the same. A block bounded over its own heights, not its patch's, is projected from where it
// is: a low block of a mountain patch is no longer as near the camera as the peak.
vec2 blocksHeightRangeM(PatchInstance patch_, ivec2 first, ivec2 last) {
    int layer = patch_.layerLevel.x;
    ivec2 span = last - first;
    if (layer < 0 || patch_.texelMap.w != 0.0 || span.x + span.y > 1) return patch_.errors.zw;
    vec2 a = texelFetch(u_blockRanges, ivec3(first, layer), 0).rg;
    vec2 b = texelFetch(u_blockRanges, ivec3(last, layer), 0).rg;
    return vec2(min(a.x, b.x), max(a.y, b.y));
}

#endif  // TERRAIN_PATCHES_GLSL
