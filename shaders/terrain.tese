// Terrain draw, tessellation evaluation: displaces each vertex by its sample in the
// patch's layer of the GPU tile pool's height array; the normal comes from central
// differences, which the one-sample apron makes available on the patch border too.
#include "Bindings.h"
#include "terrain_patches.glsl"

layout(quads, equal_spacing, ccw) in;

layout(binding = TERRAIN_BINDING_HEIGHTS) uniform sampler2DArray u_heights;
uniform mat4 u_viewProjection;  // camera-relative metres to clip space
uniform float u_cameraHeightM;
uniform int u_patchQuads;

layout(location = 0) in vec2 i_sample[];
layout(location = 1) flat in int i_instance[];
layout(location = 0) out vec3 o_fromCameraM;
layout(location = 1) out vec3 o_normal;
layout(location = 2) out float o_heightM;
layout(location = 3) flat out int o_level;

float heightAt(ivec2 texel, int layer) {
    return texelFetch(u_heights, ivec3(texel, layer), 0).r;
}

void main() {
    PatchInstance patch_ = u_instances[i_instance[0]];
    int layer = patch_.layerLevel.x;
    vec2 u = gl_TessCoord.xy;
    vec2 s = mix(mix(i_sample[0], i_sample[1], u.x), mix(i_sample[2], i_sample[3], u.x), u.y);
    ivec2 texel = ivec2(floor(s + 0.5)) + 1;  // power-of-two factors: vertices on samples
    float h = heightAt(texel, layer);
    vec2 metresPerSample = patch_.northWestAndSize.zw / float(u_patchQuads);
    float dx = heightAt(texel + ivec2(1, 0), layer) - heightAt(texel - ivec2(1, 0), layer);
    float dy = heightAt(texel - ivec2(0, 1), layer) - heightAt(texel + ivec2(0, 1), layer);
    // Rows run south: +row is −y in the world.
    o_normal = normalize(vec3(-dx / (2.0 * metresPerSample.x), -dy / (2.0 * metresPerSample.y), 1.0));
    o_heightM = h;
    o_level = patch_.layerLevel.y;
    vec2 s01 = vec2(texel - 1);
    o_fromCameraM = vec3(patch_.northWestAndSize.x + s01.x * metresPerSample.x,
                         patch_.northWestAndSize.y - s01.y * metresPerSample.y,
                         h - u_cameraHeightM);
    gl_Position = u_viewProjection * vec4(o_fromCameraM, 1.0);
}
