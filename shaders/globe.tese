// Globe draw, tessellation evaluation: each generated vertex is a patch sample (the factors
// are powers of two dividing the block's quads), placed on the ellipsoid at its height along
// its normal, camera-relative in float (globePositionM). A bare patch (layer < 0) is the
// ellipsoid itself, height 0; a virtual patch interpolates its ancestor's tile. Skirt vertices hang their top sample down the normal by the
// control stage's drop times v. The shading normal tilts the ellipsoid normal by the height
// differences across the apron, over the patch's sample spacing.
#include "Bindings.h"
#include "globe_patches.glsl"
#include "globe_heights.glsl"

layout(quads, equal_spacing, ccw) in;

uniform mat4 u_viewProjection;  // camera-relative metres to clip space

layout(location = 0) in vec2 i_sample[];
layout(location = 1) flat in int i_instance[];
layout(location = 4) patch in float i_skirtDropM;
layout(location = 5) patch in int i_debugFactor;
layout(location = 0) out vec3 o_fromCameraM;
layout(location = 1) out vec3 o_normal;
layout(location = 2) out float o_heightM;
layout(location = 3) flat out int o_level;
layout(location = 4) flat out int o_tessFactor;
layout(location = 5) out vec2 o_demSample;  // terrain.frag's clip: nothing to clip on a globe

void main() {
    GlobeInstance patch_ = u_globe[i_instance[0]];
    int layer = patch_.layerLevelFace.x;
    vec2 u = gl_TessCoord.xy;
    vec2 s = mix(mix(i_sample[0], i_sample[1], u.x), mix(i_sample[2], i_sample[3], u.x), u.y);
    ivec2 sampleXY = ivec2(floor(s + 0.5));
    // The tile sample under this patch sample, the apron included: itself for a data patch.
    vec2 texel = patch_.texelMap.xy + vec2(sampleXY) * patch_.texelMap.z + 1.0;
    bool between = patch_.texelMap.w != 0.0;
    float h = between ? heightBetween(texel, layer) : heightAt(ivec2(texel), layer);
    vec3 direction;
    precise vec3 position = globePositionM(patch_, vec2(sampleXY), h, direction);
    precise float drop = i_skirtDropM * u.y;
    position = position - drop * direction;

    o_normal = globeShadingNormal(patch_, texel, between, direction);
    o_heightM = h;
    o_level = patch_.layerLevelFace.y;
    o_tessFactor = i_debugFactor;
    o_demSample = vec2(0.0);
    o_fromCameraM = position;
    gl_Position = u_viewProjection * vec4(position, 1.0);
}
