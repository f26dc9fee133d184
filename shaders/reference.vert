// Reference draw on the plane, vertex stage: every sample of a tile of the pyramid's finest
// level is a vertex (runtime/truth PlaneReferenceScene.h); the fragment stage drops what lies
// beyond the DEM. No LOD: the index buffer is a plain grid, each cell split along its
// north-west–south-east diagonal. Positions are computed as the LOD draw computes them (DEM
// samples relative to the camera's anchor sample, then metres: surface_plane.glsl), from the
// same frame block, so both are equally precise far from the origin.
#include "terrain_frame.glsl"
#include "terrain_heights.glsl"
#include "terrain_patches.glsl"

// An instance's record: placement0.xy its north-west DEM sample minus the anchor sample
// (integers, exact in float within 2^24 samples of the camera); layerLevel.x its tile's layer
// (the tile with a one-sample apron). u_frame.tessellation.z: quads a tile side.

layout(location = 0) out vec3 o_fromCameraM;
layout(location = 1) out vec3 o_normal;
layout(location = 2) out float o_heightM;
layout(location = 3) out vec2 o_demSample;  // DEM sample (x east, y south) minus the anchor
// For reference.frag's footprint-filtered normal: the instance, where in its samples, and up.
layout(location = 4) flat out int o_instance;
layout(location = 5) out vec2 o_sample;
layout(location = 6) out vec3 o_up;

void main() {
    PatchInstance tile = u_instances[gl_InstanceID];
    int layer = tile.layerLevel.x;
    int tileSamples = u_frame.tessellation.z + 1;
    ivec2 s = ivec2(gl_VertexID % tileSamples, gl_VertexID / tileSamples);
    ivec2 texel = s + 1;  // the apron
    float h = heightAt(texel, layer);
    // Central differences over the full-resolution samples (the LOD's tessellation
    // evaluation stage does the same over its level's samples). Rows run south.
    vec2 spacing = u_frame.planeSpacing.xy;
    float dx = heightAt(texel + ivec2(1, 0), layer) - heightAt(texel - ivec2(1, 0), layer);
    float dy = heightAt(texel - ivec2(0, 1), layer) - heightAt(texel + ivec2(0, 1), layer);
    o_normal = normalize(vec3(-dx / (2.0 * spacing.x), -dy / (2.0 * spacing.y), 1.0));
    o_heightM = h;
    o_instance = gl_InstanceID;
    o_sample = vec2(s);
    o_up = vec3(0.0, 0.0, 1.0);
    precise vec2 demSample = tile.placement0.xy + vec2(s);
    o_demSample = demSample;
    precise vec2 metres = (demSample - u_frame.planeCamera.xy) * spacing;
    precise float z = h - u_frame.planeCamera.z;
    vec3 position = vec3(metres.x, -metres.y, z);  // rows run south: +row is −y
    o_fromCameraM = position;
    gl_Position = u_frame.viewProjection * vec4(position, 1.0);
}
