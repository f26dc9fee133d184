// Valdetaro et al. 2011 (LodMethod::Valdetaro2011), tessellation evaluation: the tile's
// generated vertex interpolated between its corners, and displaced by the height map at
// its texture coordinate (§6.3, the Domain Shader). Factors are not powers of two here, so
// vertices fall between samples: heights are bilinear (terrain_bilinear.glsl).
#include "Bindings.h"
#include "terrain_patches.glsl"
#include "surface_plane.glsl"
#include "terrain_bilinear.glsl"

layout(quads, equal_spacing, ccw) in;


layout(location = 0) in vec2 i_sample[];
layout(location = 1) flat in int i_instance[];
layout(location = 5) patch in int i_debugFactor;
layout(location = 0) out vec3 o_fromCameraM;
layout(location = 1) out vec3 o_normal;
layout(location = 2) out float o_heightM;
layout(location = 3) flat out int o_level;
layout(location = 4) flat out int o_tessFactor;
// The draw instance (the patch) for the patch-id view (TerrainDebugView::PatchId).
layout(location = 9) flat out int o_patch;
layout(location = 5) out vec2 o_demSample;

void main() {
    PatchInstance patch_ = u_instances[i_instance[0]];
    int layer = patch_.layerLevel.x;
    // Corners 0 and 3 are the tile's north-west and south-east samples (terrain.vert); an
    // edge vertex is a whole sample along one axis, the same from both tiles.
    precise vec2 s = i_sample[0] + gl_TessCoord.xy * (i_sample[3] - i_sample[0]);
    float h = terrainBilinearHeight(u_heights, s, layer);
    o_normal = terrainNearestNormal(u_heights, s, layer, u_frame.planeSpacing.xy * patch_.placement0.z);
    o_heightM = h;
    o_level = patch_.layerLevel.y;
    o_tessFactor = i_debugFactor;
    o_patch = i_instance[0];
    o_demSample = terrainDemSample(patch_, s);
    precise vec3 position = terrainPositionM(patch_, s, h);
    o_fromCameraM = position;
    gl_Position = u_frame.viewProjection * vec4(position, 1.0);
}
