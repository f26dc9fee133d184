// Lee & Shin 2011, the draw: the triangles triangle splitting wrote, three DEM samples each,
// placed and given normals exactly as rtin.vert and reference.vert do (heights fetched from
// the full-resolution height field); reference.frag shades them and drops what lies beyond
// the DEM.
#include "Bindings.h"
#include "terrain_frame.glsl"

layout(std430, binding = TERRAIN_BINDING_LEE_TRIANGLES) readonly buffer Triangles {
    ivec2 u_vertices[];
};
layout(binding = TERRAIN_BINDING_LEE_HEIGHTS) uniform sampler2D u_heightField;

uniform ivec2 u_rasterSize;

layout(location = 0) out vec3 o_fromCameraM;
layout(location = 1) out vec3 o_normal;
layout(location = 2) out float o_heightM;
layout(location = 3) out vec2 o_demSample;

float heightAt(ivec2 s) {
    return texelFetch(u_heightField, clamp(s, ivec2(0), u_rasterSize - 1), 0).r;
}

void main() {
    ivec2 s = u_vertices[gl_VertexID];
    float h = heightAt(s);
    float dx = heightAt(s + ivec2(1, 0)) - heightAt(s - ivec2(1, 0));
    float dy = heightAt(s - ivec2(0, 1)) - heightAt(s + ivec2(0, 1));  // rows run south
    o_normal = normalize(vec3(-dx / (2.0 * u_frame.planeSpacing.x), -dy / (2.0 * u_frame.planeSpacing.y), 1.0));
    o_heightM = h;
    precise vec2 demSample = vec2(s) - planeAnchorSample();
    o_demSample = demSample;
    precise vec2 metres = (demSample - u_frame.planeCamera.xy) * u_frame.planeSpacing.xy;
    vec3 position = vec3(metres.x, -metres.y, h - u_frame.planeCamera.z);
    o_fromCameraM = position;
    gl_Position = u_frame.viewProjection * vec4(position, 1.0);
}
