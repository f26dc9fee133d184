// Reference draw, fragment stage: the terrain's shading (terrain_shading.glsl) at location
// 0, and the world height of the full-resolution surface at location 1 (an R32F target).
// Fragments beyond the DEM's extent are discarded: the finest level's last patches
// overhang it with clamped copies of its edge, which are not data.
#include "Bindings.h"
#include "terrain_shading.glsl"

layout(location = 0) in vec3 i_fromCameraM;
layout(location = 1) in vec3 i_normal;
layout(location = 2) in float i_heightM;
layout(location = 3) in vec2 i_demSample;
#ifdef TERRAIN_REFERENCE_FRAME_BLOCK
// The reference renderers (runtime/truth ReferenceRenderer.h) hand in their frame as the
// patch draws do: the frame block.
#include "terrain_frame.glsl"
vec4 demExtent() { return u_frame.demExtent; }
TerrainShading shading() {
    return TerrainShading(u_frame.sunDirection.xyz, u_frame.heightRange.xy, u_frame.sky.rgb,
                          u_frame.sky.w);
}
#else
// The comparison methods' draws that share this stage set uniforms (runtime/draw
// TerrainFrameUniforms.h) until they take the frame block too.
uniform vec2 u_demFirstSample;  // DEM sample (0, 0) minus the anchor
uniform vec2 u_demLastSample;   // DEM sample (width − 1, height − 1) minus the anchor
uniform vec3 u_sunDirection;
uniform vec2 u_heightRangeM;
uniform vec3 u_skyColor;
uniform float u_fogDensityPerM;
vec4 demExtent() { return vec4(u_demFirstSample, u_demLastSample); }
TerrainShading shading() {
    return TerrainShading(u_sunDirection, u_heightRangeM, u_skyColor, u_fogDensityPerM);
}
#endif
layout(location = TERRAIN_FRAG_COLOR) out vec4 o_color;
layout(location = 1) out float o_heightM;

void main() {
    // A thousandth of a sample of slack: the interpolated position of the DEM's own last
    // column or row may round to just beyond it.
    const float kSlack = 1.0e-3;
    vec4 extent = demExtent();
    if (any(lessThan(i_demSample, extent.xy - kSlack)) ||
        any(greaterThan(i_demSample, extent.zw + kSlack))) {
        discard;
    }
    o_color = vec4(terrainShade(shading(), i_normal, i_heightM, i_fromCameraM), 1.0);
    o_heightM = i_heightM;
}
