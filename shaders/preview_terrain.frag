// Hillshade: Lambert from a north-west sun, a hypsometric tint, distance fog to the sky.
#include "Bindings.h"

uniform vec3 u_sunDirection;  // towards the sun, unit length
uniform vec2 u_heightRangeM;  // min, max of the DEM
uniform vec3 u_skyColor;
uniform float u_fogDensityPerM;

layout(location = 0) in vec3 i_fromCameraM;
layout(location = 1) in vec3 i_normal;
layout(location = 2) in float i_heightM;
layout(location = TERRAIN_FRAG_COLOR) out vec4 o_color;

vec3 tint(float t) {
    const vec3 low = vec3(0.34, 0.50, 0.30), mid = vec3(0.62, 0.55, 0.42), high = vec3(0.93);
    return t < 0.6 ? mix(low, mid, t / 0.6) : mix(mid, high, (t - 0.6) / 0.4);
}

void main() {
    vec3 n = normalize(i_normal);
    float lambert = max(dot(n, u_sunDirection), 0.0);
    float t = clamp((i_heightM - u_heightRangeM.x) / max(u_heightRangeM.y - u_heightRangeM.x, 1.0), 0.0, 1.0);
    vec3 lit = tint(t) * (0.25 + 0.75 * lambert);
    float fog = 1.0 - exp(-u_fogDensityPerM * length(i_fromCameraM));
    o_color = vec4(mix(lit, u_skyColor, fog), 1.0);
}
