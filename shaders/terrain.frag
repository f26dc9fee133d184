// Terrain draw, fragment stage: the shaded view (terrain_shading.glsl, shared with the
// reference renderer so the two differ only where geometry or normals do) or a debug colour
// (patch level, block tessellation factor) under the same sun and fog. Fragments beyond the
// DEM's extent — the overhang of a level's last patches — are discarded.
#include "Bindings.h"
#include "terrain_shading.glsl"

uniform int u_debugView;  // TerrainDebugView: 0 shaded, 1 level, 2 tessellation factor
uniform vec2 u_demFirstSample;  // terrain_patches.glsl
uniform vec2 u_demLastSample;

layout(location = 0) in vec3 i_fromCameraM;
layout(location = 1) in vec3 i_normal;
layout(location = 2) in float i_heightM;
layout(location = 3) flat in int i_level;
layout(location = 4) flat in int i_tessFactor;
layout(location = 5) in vec2 i_demSample;
layout(location = TERRAIN_FRAG_COLOR) out vec4 o_color;

// Interpolation may put the DEM's own edge a hair outside it.
const float kEdgeToleranceSamples = 1.0e-3;

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
    if (any(lessThan(i_demSample, u_demFirstSample - kEdgeToleranceSamples)) ||
        any(greaterThan(i_demSample, u_demLastSample + kEdgeToleranceSamples))) {
        discard;
    }
    if (u_debugView == 0) {
        o_color = vec4(terrainShade(i_normal, i_heightM, i_fromCameraM), 1.0);
        return;
    }
    vec3 base = u_debugView == 1 ? levelColor(i_level) : tessFactorColor(i_tessFactor);
    o_color = vec4(terrainShadeColor(base, i_normal, i_fromCameraM), 1.0);
}
