// Livny et al. 2007 (LodMethod::Livny2007), tessellation evaluation: a vertex of a triangular
// tile (its edge's ends a, b and the patch's centre c) placed by its barycentric coordinates
// and displaced by the patch's heights (§3: "the vertex processor … fetches the elevation from
// cached textures"), bilinear between samples (terrain_bilinear.glsl). s = a + v (b − a) +
// w (c − a) keeps the patch border's vertices on whole samples, bit-identical from both
// patches sharing the border.
#include "Bindings.h"
#include "terrain_patches.glsl"
#include "surface_plane.glsl"
#include "terrain_bilinear.glsl"

layout(triangles, equal_spacing, ccw) in;


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
    precise vec2 s = i_sample[0] + gl_TessCoord.y * (i_sample[1] - i_sample[0]) +
                     gl_TessCoord.z * (i_sample[2] - i_sample[0]);
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
