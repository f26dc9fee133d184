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
// The frame (the DEM's extent around the anchor, the look) is the frame block, as the patch
// draws have it: the reference renderers (runtime/truth ReferenceBatch) and the comparison
// methods' meshes (runtime/draw PlaneFrame) bind it.
#include "terrain_frame.glsl"
layout(location = TERRAIN_FRAG_COLOR) out vec4 o_color;
layout(location = 1) out float o_heightM;

#ifdef TERRAIN_REFERENCE_FOOTPRINT
// The reference renderers' draws (runtime/truth ReferenceBatch): the normal filtered to the
// pixel's footprint as the patch draws filter theirs (terrain_footprint.glsl), over the
// instance's tile; the comparison methods that share this stage shade their vertices'.
#include "terrain_surface.glsl"
#include "terrain_footprint.glsl"
layout(location = 4) flat in int i_instance;
layout(location = 5) in vec2 i_sample;  // the instance's samples, apron excluded
layout(location = 6) in vec3 i_up;
#endif

void main() {
#ifdef TERRAIN_REFERENCE_FOOTPRINT
    float footprint = sampleFootprint(i_sample);
    // Before the discard, as derivatives need.
    vec2 sampleDx = dFdx(i_sample), sampleDy = dFdy(i_sample);
#endif
    float meshCoastWidthM = fwidth(i_heightM);
    // A thousandth of a sample of slack: the interpolated position of the DEM's own last
    // column or row may round to just beyond it.
    const float kSlack = 1.0e-3;
    vec4 extent = u_frame.demExtent;
    if (any(lessThan(i_demSample, extent.xy - kSlack)) ||
        any(greaterThan(i_demSample, extent.zw + kSlack))) {
        discard;
    }
    TerrainShading shading = TerrainShading(u_frame.sunDirection.xyz, u_frame.heightRange.xy,
                                            u_frame.sky.rgb, u_frame.sky.w, u_frame.heightRange.zw);
#ifdef TERRAIN_REFERENCE_FOOTPRINT
    FootprintSurface ground = footprintSurface(i_instance, i_sample, footprint);
    vec3 normal = footprintNormal(i_instance, ground, normalize(i_normal), normalize(i_up));
    float heightM = mix(i_heightM, ground.heightM, ground.weight);
    float coastWidthM = mix(meshCoastWidthM, heightAcrossPixel(ground.slope, sampleDx, sampleDy),
                            ground.weight);
#else
    vec3 normal = i_normal;
    float heightM = i_heightM;
    float coastWidthM = meshCoastWidthM;
#endif
    o_color = vec4(terrainShade(shading, normal, heightM, coastWidthM, i_fromCameraM), 1.0);
    o_heightM = i_heightM;
}
