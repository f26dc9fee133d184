// CDLOD, Strugar 2009, "Continuous Distance-Dependent Level of Detail for Rendering
// Heightmaps" (LodMethod::Cdlod), vertex stage: every selected patch is one instance of a
// regular grid of its level's samples; each vertex morphs towards the grid of the next
// coarser level as its distance to the camera approaches the end of the patch's range, so
// a patch meets a coarser neighbour on that neighbour's grid and a level change is a
// continuous blend, not a pop (Strugar's vertex morphing; the paper is not among
// ../shared/papers, so no section is cited).
//
// Ranges (LodQuadtree's SplitRule::ProjectedSpacing): a patch of level l is drawn beyond
// R_l = γ · s_l / τ and its parent would be beyond R_{l−1} = 2 R_l, so its vertices morph over
// [morphStart, 2 R_l] with morphStart = R_l + 0.66 · (2 R_l − R_l) (Strugar's default
// morph-start ratio); the coarsest level does not morph.
#include "Bindings.h"
#include "terrain_patches.glsl"
#include "surface_plane.glsl"
#include "terrain_bilinear.glsl"

uniform int u_gridQuads;        // the patch's quads a side
uniform float u_rangePerMetre;  // γ / τ: R_l = u_rangePerMetre · s_l
uniform float u_morphStartRatio;

layout(location = 0) out vec3 o_fromCameraM;
layout(location = 1) out vec3 o_normal;
layout(location = 2) out float o_heightM;
layout(location = 3) flat out int o_level;
layout(location = 4) flat out int o_tessFactor;
// The draw instance (the patch) for the patch-id view (TerrainDebugView::PatchId).
layout(location = 9) flat out int o_patch;
layout(location = 5) out vec2 o_demSample;

void main() {
    PatchInstance patch_ = u_instances[gl_InstanceID];
    int layer = patch_.layerLevel.x;
    int level = patch_.layerLevel.y;
    int samples = u_gridQuads + 1;
    vec2 grid = vec2(gl_VertexID % samples, gl_VertexID / samples);

    float spacingM = max(u_frame.planeSpacing.x, u_frame.planeSpacing.y) * patch_.placement0.z;
    float rangeM = u_rangePerMetre * spacingM;  // R_l
    float morphEnd = 2.0 * rangeM;
    float morphStart = rangeM + u_morphStartRatio * (morphEnd - rangeM);
    vec3 unmorphed = terrainPositionM(patch_, grid, terrainTexel(u_heights, ivec2(grid) + 1, layer));
    float k = level == 0 ? 0.0 : clamp((length(unmorphed) - morphStart) / (morphEnd - morphStart), 0.0, 1.0);
    // Strugar's morphVertex: odd grid positions slide onto their even neighbours.
    vec2 odd = fract(grid * 0.5) * 2.0;
    precise vec2 s = grid - odd * k;
    float h = terrainBilinearHeight(u_heights, s, layer);
    o_normal = terrainNearestNormal(u_heights, s, layer, u_frame.planeSpacing.xy * patch_.placement0.z);
    o_heightM = h;
    o_level = level;
    o_tessFactor = int(round(float(u_gridQuads) * (1.0 - 0.5 * k)));
    o_patch = gl_InstanceID;
    o_demSample = terrainDemSample(patch_, s);
    precise vec3 position = terrainPositionM(patch_, s, h);
    o_fromCameraM = position;
    gl_Position = u_frame.viewProjection * vec4(position, 1.0);
}
