// Reference draw, vertex stage: every sample of a tile of the pyramid's finest level is a
// vertex (ReferenceRenderer.h); the fragment stage drops what lies beyond the DEM. No LOD: the index buffer is a plain grid, each cell split
// along its north-west–south-east diagonal. Positions are computed as the LOD draw computes
// them (DEM samples relative to the camera's anchor sample, then metres), so both are
// equally precise far from the origin.
#include "Bindings.h"

struct ReferenceTile {
    // x, y: the tile's north-west DEM sample minus the anchor sample (integers, exact in
    // float within 2^24 samples of the camera); z: texture-array layer.
    vec4 originLayer;
};

layout(std430, binding = TERRAIN_BINDING_PATCH_INSTANCES) readonly buffer ReferenceTiles {
    ReferenceTile u_tiles[];
};
layout(binding = TERRAIN_BINDING_HEIGHTS) uniform sampler2DArray u_heights;  // tiles + apron

uniform int u_tileSamples;            // samples a side of a tile, without apron
uniform vec2 u_cameraSampleFraction;  // camera x, y in DEM samples minus the anchor, [0, 1)
uniform vec2 u_sampleSpacingM;        // metres per DEM sample, east and south
uniform float u_cameraHeightM;
uniform mat4 u_viewProjection;        // camera-relative metres to clip space

layout(location = 0) out vec3 o_fromCameraM;
layout(location = 1) out vec3 o_normal;
layout(location = 2) out float o_heightM;
layout(location = 3) out vec2 o_demSample;  // DEM sample (x east, y south) minus the anchor

float heightAt(ivec2 texel, int layer) {
    return texelFetch(u_heights, ivec3(texel, layer), 0).r;
}

void main() {
    ReferenceTile tile = u_tiles[gl_InstanceID];
    int layer = int(tile.originLayer.z);
    ivec2 s = ivec2(gl_VertexID % u_tileSamples, gl_VertexID / u_tileSamples);
    ivec2 texel = s + 1;  // the apron
    float h = heightAt(texel, layer);
    // Central differences over the full-resolution samples (the LOD's tessellation
    // evaluation stage does the same over its level's samples). Rows run south.
    float dx = heightAt(texel + ivec2(1, 0), layer) - heightAt(texel - ivec2(1, 0), layer);
    float dy = heightAt(texel - ivec2(0, 1), layer) - heightAt(texel + ivec2(0, 1), layer);
    o_normal = normalize(vec3(-dx / (2.0 * u_sampleSpacingM.x), -dy / (2.0 * u_sampleSpacingM.y), 1.0));
    o_heightM = h;
    precise vec2 demSample = tile.originLayer.xy + vec2(s);
    o_demSample = demSample;
    precise vec2 metres = (demSample - u_cameraSampleFraction) * u_sampleSpacingM;
    precise float z = h - u_cameraHeightM;
    vec3 position = vec3(metres.x, -metres.y, z);  // rows run south: +row is −y
    o_fromCameraM = position;
    gl_Position = u_viewProjection * vec4(position, 1.0);
}
