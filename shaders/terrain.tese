// Terrain draw, tessellation evaluation, on either surface: each generated vertex is a patch
// sample (the factors are powers of two dividing the block's quads), its height read from the
// patch's tile (its own; an ancestor's between that tile's samples for a virtual patch; 0 for
// a bare one: terrain_heights.glsl), placed camera-relative by the surface
// (surfacePositionM). Skirt vertices take their top sample's position and normal and are
// lowered by the control stage's drop times v, down the surface's vertical. The shading normal
// comes from the heights across the sample (central differences, which the one-sample apron
// makes available on the patch border too).
#include "Bindings.h"
#include "terrain_patches.glsl"
#include "terrain_surface.glsl"

layout(quads, equal_spacing, ccw) in;

layout(location = 0) in vec2 i_sample[];
layout(location = 1) flat in int i_instance[];
layout(location = 4) patch in float i_skirtDropM;
layout(location = 5) patch in int i_debugFactor;
layout(location = 0) out vec3 o_fromCameraM;
layout(location = 1) out vec3 o_normal;
layout(location = 2) out float o_heightM;
layout(location = 3) flat out int o_level;
layout(location = 4) flat out int o_tessFactor;
// The draw instance (the patch) for the patch-id view (TerrainDebugView::PatchId).
layout(location = 9) flat out int o_patch;
layout(location = 5) out vec2 o_demSample;  // minus the anchor: the fragment stage clips
// Where the imagery is looked up (surfaceImageryUv), and what a native tile owns there.
layout(location = 10) out vec2 o_imageryUv;
#ifdef TERRAIN_FRAGMENT_NORMALS
// For the fragment stage's normals (terrain.frag): where in the patch's samples, and the
// surface's vertical there (the patch is o_patch's).
layout(location = 6) out vec2 o_patchSample;
layout(location = 8) out vec3 o_up;
#endif

void main() {
    PatchInstance patch_ = u_instances[i_instance[0]];
    int layer = patch_.layerLevel.x;
    vec2 u = gl_TessCoord.xy;
    vec2 s = mix(mix(i_sample[0], i_sample[1], u.x), mix(i_sample[2], i_sample[3], u.x), u.y);
    ivec2 sampleXY = ivec2(floor(s + 0.5));
    // The tile sample under this patch sample, the apron included: itself for a data patch.
    vec2 texel = tileTexel(patch_.texelMap, vec2(sampleXY));
    float h = tileHeight(texel, patch_.texelMap.w, layer);
    vec3 up;
    precise float drop = i_skirtDropM * u.y;
    precise vec3 position = surfacePositionM(patch_, vec2(sampleXY), h, drop, up);
    o_normal = surfaceShadingNormal(patch_, texel, patch_.texelMap.w, up);
    o_heightM = h;
    o_level = patch_.layerLevel.y;
    o_tessFactor = i_debugFactor;
    o_patch = i_instance[0];
    o_demSample = surfaceDemSample(patch_, vec2(sampleXY));
#ifdef TERRAIN_FRAGMENT_NORMALS
    o_patchSample = vec2(sampleXY);
    o_up = up;
#endif
    o_imageryUv = surfaceImageryUv(patch_, vec2(sampleXY));
    o_fromCameraM = position;
    gl_Position = u_frame.viewProjection * vec4(position, 1.0);
}
