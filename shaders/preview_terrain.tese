// Preview displacement: height from the texture at the generated vertex, normal from
// central differences of the neighbouring samples. Positions are camera-relative.
#include "Bindings.h"

layout(quads, equal_spacing, ccw) in;

layout(binding = TERRAIN_BINDING_HEIGHTS) uniform sampler2D u_heights;
uniform mat4 u_viewProjection;   // camera-relative world (metres) to clip space
uniform vec3 u_cameraSample;
uniform float u_sampleSpacingM;

layout(location = 0) in vec2 i_sample[];
layout(location = 0) out vec3 o_fromCameraM;
layout(location = 1) out vec3 o_normal;
layout(location = 2) out float o_heightM;

float heightAt(vec2 sampleXY) {
    ivec2 last = textureSize(u_heights, 0) - 1;
    return texelFetch(u_heights, clamp(ivec2(sampleXY), ivec2(0), last), 0).r;
}

void main() {
    vec2 u = gl_TessCoord.xy;
    vec2 s = mix(mix(i_sample[0], i_sample[1], u.x), mix(i_sample[2], i_sample[3], u.x), u.y);
    s = floor(s + 0.5);  // power-of-two factors: every vertex is a sample
    float h = heightAt(s);
    float dx = heightAt(s + vec2(1, 0)) - heightAt(s - vec2(1, 0));
    float dz = heightAt(s + vec2(0, 1)) - heightAt(s - vec2(0, 1));
    o_normal = normalize(vec3(-dx, 2.0 * u_sampleSpacingM, -dz));
    o_heightM = h;
    o_fromCameraM = vec3((s.x - u_cameraSample.x) * u_sampleSpacingM, h - u_cameraSample.y,
                         (s.y - u_cameraSample.z) * u_sampleSpacingM);
    gl_Position = u_viewProjection * vec4(o_fromCameraM, 1.0);
}
