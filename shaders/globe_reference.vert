// Globe reference draw, vertex stage: every sample of a region's grid is a vertex
// (GlobeReferenceRenderer.h), placed on the ellipsoid as the globe draw places it
// (globePositionM, surface_globe.glsl) and shaded with the same normal. No LOD: a plain
// indexed grid, each cell split along its north-west–south-east diagonal, no skirts.
#include "Bindings.h"
#include "surface_globe.glsl"

uniform mat4 u_viewProjection;  // camera-relative metres to clip space
uniform int u_patchQuads;       // N − 1

layout(location = 0) out vec3 o_fromCameraM;
layout(location = 1) out vec3 o_normal;
layout(location = 2) out float o_heightM;
layout(location = 3) out vec2 o_demSample;  // reference.frag's clip: nothing to clip on a globe

void main() {
    PatchInstance region = u_instances[gl_InstanceID];
    int layer = region.layerLevel.x;
    vec2 s = vec2(gl_VertexID % (u_patchQuads + 1), gl_VertexID / (u_patchQuads + 1));
    vec2 texel = tileTexel(region.texelMap, s);
    bool between = region.texelMap.w != 0.0;
    float h = tileHeight(texel, between, layer);
    vec3 direction;
    precise vec2 uv = s / float(u_patchQuads);
    vec3 position = globePositionM(region, uv, h, direction);
    o_normal = globeShadingNormal(region, texel, between, direction);
    o_heightM = h;
    o_demSample = vec2(0.0);
    o_fromCameraM = position;
    gl_Position = u_viewProjection * vec4(position, 1.0);
}
