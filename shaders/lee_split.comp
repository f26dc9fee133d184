// Lee & Shin 2011, vertex splitting (§2.3, §3): one pass per quadtree level. Each block
// (its centre vertex) whose LOD flag f is 1 is split into its four children, which enter the
// next pass unless their bounding sphere is outside the frustum (Fig. 10); a block with
// f = 0 is a leaf and goes to the leaf list, so later passes never evaluate it again (the
// paper keeps it in the stream with w = 0 for the same reason). A split block sets its flag
// at its centre for triangle splitting. A finest block (h = 1) that splits becomes its four
// quads, drawn at full resolution.
#include "lee_quadtree.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = TERRAIN_BINDING_LEE_INPUT) readonly buffer Blocks { ivec2 u_blocks[]; };
layout(std430, binding = TERRAIN_BINDING_LEE_OUTPUT) writeonly buffer Children {
    ivec2 u_children[];
};
// North-west corner and size in quads of each leaf block.
layout(std430, binding = TERRAIN_BINDING_LEE_LEAVES) writeonly buffer Leaves { ivec4 u_leaves[]; };
layout(binding = TERRAIN_IMAGE_LEE_SPLIT_FLAGS, r8ui) uniform writeonly uimage2D u_splitFlags;

uniform int u_pass;
uniform int u_halfSize;  // h of this pass's blocks: 2^level
uniform int u_level;
uniform uint u_blockCapacity;  // of the input and the output lists
uniform uint u_leafCapacity;

void appendLeaf(ivec2 northWest, int size) {
    uint slot = atomicAdd(c_leaves, 1u);
    if (slot < u_leafCapacity) u_leaves[slot] = ivec4(northWest, size, 0);
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= min(c_nodes[u_pass], u_blockCapacity)) return;
    ivec2 c = u_blocks[i];
    int h = u_halfSize;
    if (!lodFlag(c, h, u_level)) {
        appendLeaf(c - h, 2 * h);
        return;
    }
    imageStore(u_splitFlags, c, uvec4(1u));
    for (int child = 0; child < 4; ++child) {
        ivec2 side = ivec2(child & 1, child >> 1);
        if (h == 1) {
            ivec2 quad = c - 1 + side;
            if (insideRaster(quad)) appendLeaf(quad, 1);
            continue;
        }
        int childHalf = h / 2;
        ivec2 centre = c + childHalf * (2 * side - 1);
        if (!insideRaster(centre - childHalf)) continue;
        if (!sphereVisible(blockSphere(centre, childHalf, u_level - 1))) continue;
        uint slot = atomicAdd(c_nodes[u_pass + 1], 1u);
        if (slot < u_blockCapacity) u_children[slot] = centre;
    }
}
