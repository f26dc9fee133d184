// Valdetaro et al. 2011 (LodMethod::Valdetaro2011), tessellation evaluation: the tile's
// generated vertex interpolated between its corners, and displaced by the height map at
// its texture coordinate (§6.3, the Domain Shader). Factors are not powers of two here, so
// vertices fall between samples: the height is the bilinear interpolation of the four
// samples around it, done by hand from texelFetch with float weights (a filtering unit's
// few bits of sub-texel precision would give the two sides of a patch border different
// heights), and an edge vertex, at the same DEM position from both tiles, gets the same
// height from both. The normal is the nearest sample's central differences.
#include "Bindings.h"
#include "terrain_patches.glsl"

layout(quads, equal_spacing, ccw) in;

layout(binding = TERRAIN_BINDING_HEIGHTS) uniform sampler2DArray u_heights;
uniform mat4 u_viewProjection;  // camera-relative metres to clip space

layout(location = 0) in vec2 i_sample[];
layout(location = 1) flat in int i_instance[];
layout(location = 5) patch in int i_debugFactor;
layout(location = 0) out vec3 o_fromCameraM;
layout(location = 1) out vec3 o_normal;
layout(location = 2) out float o_heightM;
layout(location = 3) flat out int o_level;
layout(location = 4) flat out int o_tessFactor;
layout(location = 5) out vec2 o_demSample;

float heightAt(ivec2 texel, int layer) {
    return texelFetch(u_heights, ivec3(texel, layer), 0).r;
}

void main() {
    PatchInstance patch_ = u_instances[i_instance[0]];
    int layer = patch_.layerLevel.x;
    // Corners 0 and 3 are the tile's north-west and south-east samples (terrain.vert).
    precise vec2 s = i_sample[0] + gl_TessCoord.xy * (i_sample[3] - i_sample[0]);
    ivec2 cell = ivec2(floor(s));
    precise vec2 f = s - vec2(cell);
    ivec2 texel = cell + 1;  // the apron
    float h00 = heightAt(texel, layer), h10 = heightAt(texel + ivec2(1, 0), layer);
    float h01 = heightAt(texel + ivec2(0, 1), layer), h11 = heightAt(texel + ivec2(1, 1), layer);
    precise float h = mix(mix(h00, h10, f.x), mix(h01, h11, f.x), f.y);

    ivec2 nearest = ivec2(floor(s + 0.5)) + 1;
    vec2 metresPerSample = u_sampleSpacingM * patch_.originAndStep.z;
    float dx = heightAt(nearest + ivec2(1, 0), layer) - heightAt(nearest - ivec2(1, 0), layer);
    float dy = heightAt(nearest - ivec2(0, 1), layer) - heightAt(nearest + ivec2(0, 1), layer);
    o_normal = normalize(vec3(-dx / (2.0 * metresPerSample.x), -dy / (2.0 * metresPerSample.y), 1.0));
    o_heightM = h;
    o_level = patch_.layerLevel.y;
    o_tessFactor = i_debugFactor;
    o_demSample = terrainDemSample(patch_, s);
    precise vec3 position = terrainPositionM(patch_, s, h);
    o_fromCameraM = position;
    gl_Position = u_viewProjection * vec4(position, 1.0);
}
