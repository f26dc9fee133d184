// Globe reference draw, vertex stage: every sample of a region's grid is a vertex
// (runtime/truth GlobeReferenceScene.h), placed on the ellipsoid as the globe draw places it
// (globePositionM, surface_globe.glsl) and shaded with the same normal, from the same frame
// block. No LOD: a plain indexed grid, each cell split along its north-west–south-east
// diagonal, no skirts. u_frame.tessellation.z: quads a region side (N − 1).
#include "terrain_frame.glsl"
#include "surface_globe.glsl"

layout(location = 0) out vec3 o_fromCameraM;
layout(location = 1) out vec3 o_normal;
layout(location = 2) out float o_heightM;
layout(location = 3) out vec2 o_demSample;  // reference.frag's clip: nothing to clip on a globe
// For reference.frag's footprint-filtered normal: the region, where in its samples, and up.
layout(location = 4) flat out int o_instance;
layout(location = 5) out vec2 o_sample;
layout(location = 6) out vec3 o_up;

void main() {
    PatchInstance region = u_instances[gl_InstanceID];
    int layer = region.layerLevel.x;
    int patchQuads = u_frame.tessellation.z;
    vec2 s = vec2(gl_VertexID % (patchQuads + 1), gl_VertexID / (patchQuads + 1));
    vec2 texel = tileTexel(region.texelMap, s);
    float h = tileHeight(texel, region.texelMap.w, layer);
    vec3 direction;
    precise vec2 uv = s / float(patchQuads);
    vec3 position = globePositionM(region, uv, h, direction);
    o_normal = globeShadingNormal(region, texel, region.texelMap.w, direction);
    o_heightM = h;
    o_instance = gl_InstanceID;
    o_sample = s;
    o_up = direction;
    o_demSample = vec2(0.0);
    o_fromCameraM = position;
    gl_Position = u_frame.viewProjection * vec4(position, 1.0);
}
