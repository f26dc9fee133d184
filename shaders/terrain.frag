// Terrain draw, fragment stage: hillshade from a directional sun over a hypsometric tint,
// or a debug colour (patch level, block tessellation factor), then distance fog to the
// sky colour.
#include "Bindings.h"

uniform vec3 u_sunDirection;  // towards the sun, unit length, world frame
uniform vec2 u_heightRangeM;  // min, max of the DEM
uniform vec3 u_skyColor;
uniform float u_fogDensityPerM;
uniform int u_debugView;  // TerrainDebugView: 0 shaded, 1 level, 2 tessellation factor

layout(location = 0) in vec3 i_fromCameraM;
layout(location = 1) in vec3 i_normal;
layout(location = 2) in float i_heightM;
layout(location = 3) flat in int i_level;
layout(location = 4) flat in int i_tessFactor;
layout(location = TERRAIN_FRAG_COLOR) out vec4 o_color;

vec3 tint(float t) {
    const vec3 low = vec3(0.34, 0.50, 0.30), mid = vec3(0.62, 0.55, 0.42), high = vec3(0.93);
    return t < 0.6 ? mix(low, mid, t / 0.6) : mix(mid, high, (t - 0.6) / 0.4);
}

vec3 levelColor(int level) {
    const vec3 palette[6] = vec3[](vec3(0.90, 0.30, 0.25), vec3(0.95, 0.65, 0.20),
                                   vec3(0.85, 0.85, 0.25), vec3(0.35, 0.75, 0.35),
                                   vec3(0.30, 0.60, 0.90), vec3(0.60, 0.40, 0.85));
    return palette[level % 6];
}

// Coarse to fine, cold to hot: factor 1 dark blue, 2 blue, 4 cyan, 8 green, 16 yellow,
// 32 orange, 64 and more red.
vec3 tessFactorColor(int factor) {
    const vec3 palette[7] = vec3[](vec3(0.15, 0.15, 0.55), vec3(0.20, 0.40, 0.95),
                                   vec3(0.20, 0.80, 0.90), vec3(0.30, 0.80, 0.30),
                                   vec3(0.95, 0.90, 0.25), vec3(0.95, 0.55, 0.15),
                                   vec3(0.90, 0.20, 0.20));
    return palette[clamp(findMSB(max(factor, 1)), 0, 6)];
}

void main() {
    vec3 n = normalize(i_normal);
    float lambert = max(dot(n, u_sunDirection), 0.0);
    float t = clamp((i_heightM - u_heightRangeM.x) / max(u_heightRangeM.y - u_heightRangeM.x, 1.0),
                    0.0, 1.0);
    vec3 base = u_debugView == 1 ? levelColor(i_level)
              : u_debugView == 2 ? tessFactorColor(i_tessFactor)
                                 : tint(t);
    vec3 lit = base * (0.25 + 0.75 * lambert);
    float fog = 1.0 - exp(-u_fogDensityPerM * length(i_fromCameraM));
    o_color = vec4(mix(lit, u_skyColor, fog), 1.0);
}
