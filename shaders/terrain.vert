// Terrain draw, vertex stage: one quad patch primitive per tessellation block, four
// corners each, for every drawn patch (instance). Corners are in patch samples.
#include "Bindings.h"

uniform int u_blocksPerSide;
uniform int u_blockQuads;

layout(location = 0) out vec2 o_sample;     // corner: (column, row) in the patch's samples
layout(location = 1) flat out int o_instance;

void main() {
    int block = gl_VertexID >> 2;
    ivec2 blockXY = ivec2(block % u_blocksPerSide, block / u_blocksPerSide);
    ivec2 corner = ivec2(gl_VertexID & 1, (gl_VertexID >> 1) & 1);  // (0,0) (1,0) (0,1) (1,1)
    o_sample = vec2((blockXY + corner) * u_blockQuads);
    o_instance = gl_InstanceID;
}
