// Patch draws, vertex stage: attribute-less corners of every quad patch primitive of an
// instance (a drawn patch): its tessellation blocks, then its skirts (terrain_primitives.glsl).
// The terrain draw on either surface and the comparison methods' tessellated draws share it.
// Corners are in the patch's samples; the control stage picks the factors.
#include "Bindings.h"
#include "terrain_primitives.glsl"

layout(location = 0) out vec2 o_sample;  // corner: (column, row) in the patch's samples
layout(location = 1) flat out int o_instance;
layout(location = 2) flat out int o_primitive;

void main() {
    int primitive = gl_VertexID >> 2;
    ivec2 corner = ivec2(gl_VertexID & 1, (gl_VertexID >> 1) & 1);  // (0,0) (1,0) (0,1) (1,1)
    int blocksPerSide = u_frame.tessellation.x;
    int blockQuads = u_frame.tessellation.y;
    int blocks = blocksPerSide * blocksPerSide;
    ivec2 sampleXY;
    if (primitive < blocks) {
        ivec2 blockXY = ivec2(primitive % blocksPerSide, primitive / blocksPerSide);
        sampleXY = (blockXY + corner) * blockQuads;
    } else {
        // A skirt: corner.x picks the edge's end (u), corner.y the top or bottom row (v),
        // which share their samples; the evaluation stage lowers v = 1.
        int skirt = primitive - blocks;
        int edge = skirt / blocksPerSide;
        ivec2 a, b;
        terrainEdgeEnds(edge, a, b);
        ivec2 blockXY = terrainSkirtBlock(edge, skirt % blocksPerSide);
        sampleXY = (blockXY + (corner.x == 0 ? a : b)) * blockQuads;
    }
    o_sample = vec2(sampleXY);
    o_instance = gl_InstanceID;
    o_primitive = primitive;
}
