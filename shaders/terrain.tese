// Terrain draw, tessellation evaluation: places each generated vertex on its sample of the
// patch's layer of the GPU tile pool's height array (the factors are powers of two
// dividing the block's quads, so every vertex is a sample). Skirt vertices take their top
// sample's position and normal and are lowered by the control stage's drop times v. The
// normal comes from central differences, which the one-sample apron makes available on
// the patch border too.
#include "Bindings.h"
#include "terrain_patches.glsl"

layout(quads, equal_spacing, ccw) in;

layout(binding = TERRAIN_BINDING_HEIGHTS) uniform sampler2DArray u_heights;
uniform mat4 u_viewProjection;  // camera-relative metres to clip space

layout(location = 0) in vec2 i_sample[];
layout(location = 1) flat in int i_instance[];
layout(location = 4) patch in float i_skirtDropM;
layout(location = 5) patch in int i_debugFactor;
layout(location = 0) out vec3 o_fromCameraM;
layout(location = 1) out vec3 o_normal;
layout(location = 2) out float o_heightM;
layout(location = 3) flat out int o_level;
layout(location = 4) flat out int o_tessFactor;
layout(location = 5) out vec2 o_demSample;  // minus the anchor: the fragment stage clips
// For the fragment stage's normals (terrain.frag, TERRAIN_FRAGMENT_NORMALS): where in the
// patch's samples, in which layer, and how far apart its samples are.
layout(location = 6) out vec2 o_patchSample;
layout(location = 7) flat out int o_layer;
layout(location = 8) flat out vec2 o_metresPerSample;

float heightAt(ivec2 texel, int layer) {
    return texelFetch(u_heights, ivec3(texel, layer), 0).r;
}

void main() {
    PatchInstance patch_ = u_instances[i_instance[0]];
    int layer = patch_.layerLevel.x;
    vec2 u = gl_TessCoord.xy;
    vec2 s = mix(mix(i_sample[0], i_sample[1], u.x), mix(i_sample[2], i_sample[3], u.x), u.y);
    ivec2 sampleXY = ivec2(floor(s + 0.5));
    ivec2 texel = sampleXY + 1;  // the apron
    float h = heightAt(texel, layer);
    vec2 metresPerSample = u_sampleSpacingM * patch_.originAndStep.z;
    float dx = heightAt(texel + ivec2(1, 0), layer) - heightAt(texel - ivec2(1, 0), layer);
    float dy = heightAt(texel - ivec2(0, 1), layer) - heightAt(texel + ivec2(0, 1), layer);
    // Rows run south: +row is −y in the world.
    o_normal = normalize(vec3(-dx / (2.0 * metresPerSample.x), -dy / (2.0 * metresPerSample.y), 1.0));
    o_heightM = h;
    o_level = patch_.layerLevel.y;
    o_tessFactor = i_debugFactor;
    o_demSample = terrainDemSample(patch_, vec2(sampleXY));
    o_patchSample = vec2(sampleXY);
    o_layer = layer;
    o_metresPerSample = metresPerSample;
    // Blocks have no drop; a skirt's top row (v = 0) is exactly the patch's edge.
    precise vec3 position = terrainPositionM(patch_, vec2(sampleXY), h);
    precise float drop = i_skirtDropM * u.y;
    position.z = position.z - drop;
    o_fromCameraM = position;
    gl_Position = u_viewProjection * vec4(position, 1.0);
}
