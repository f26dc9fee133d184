// Globe reference draw, vertex stage: every sample of a region's grid is a vertex
// (GlobeReferenceRenderer.h), placed on the ellipsoid as the globe draw places it
// (globePositionM) and shaded with the same normal (globe_heights.glsl). No LOD: a plain
// indexed grid, each cell split along its north-west–south-east diagonal, no skirts.
#include "Bindings.h"
#include "globe_patches.glsl"
#include "globe_heights.glsl"

uniform mat4 u_viewProjection;  // camera-relative metres to clip space

layout(location = 0) out vec3 o_fromCameraM;
layout(location = 1) out vec3 o_normal;
layout(location = 2) out float o_heightM;
layout(location = 3) out vec2 o_demSample;  // reference.frag's clip: nothing to clip on a globe

void main() {
    GlobeInstance region = u_globe[gl_InstanceID];
    int layer = region.layerLevelFace.x;
    vec2 s = vec2(gl_VertexID % (u_patchQuads + 1), gl_VertexID / (u_patchQuads + 1));
    vec2 texel = region.texelMap.xy + s * region.texelMap.z + 1.0;
    bool between = region.texelMap.w != 0.0;
    float h = between ? heightBetween(texel, layer) : heightAt(ivec2(texel), layer);
    vec3 direction;
    vec3 position = globePositionM(region, s, h, direction);
    o_normal = globeShadingNormal(region, texel, between, direction);
    o_heightM = h;
    o_demSample = vec2(0.0);
    o_fromCameraM = position;
    gl_Position = u_viewProjection * vec4(position, 1.0);
}
