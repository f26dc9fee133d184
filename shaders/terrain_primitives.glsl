// The primitives of one patch draw instance (a drawn patch, on either surface); the vertex
// stage needs only these.
//
// Primitives of an instance (quad patches of 4 vertices, vertex id = 4 · primitive + corner):
//   [0, K²)         tessellation block (bx, by) = (p % K, p / K), row-major, K =
//                   u_frame.tessellation.x (blocks per side; .y: quads a block side, B);
//   [K², K² + 4K)   skirt q = p − K²: hangs from edge e = q / K of border block i = q % K,
//                   e in GL's outer-level order (see terrainSkirtBlock).
// Block domain: u runs along the patch's columns, v along its rows, so gl_TessLevelOuter[0]
// is the block's u = 0 edge ("west"), [1] v = 0 ("north"), [2] u = 1 ("east"), [3] v = 1
// ("south"). Skirt domain: u along the edge, v down (0: the edge).
#ifndef TERRAIN_PRIMITIVES_GLSL
#define TERRAIN_PRIMITIVES_GLSL

#include "terrain_frame.glsl"

const ivec2 kEdgeNeighbour[4] = ivec2[](ivec2(-1, 0), ivec2(0, -1), ivec2(1, 0), ivec2(0, 1));

// The border block a skirt hangs from: edge e (GL order) of the i-th block along that side.
ivec2 terrainSkirtBlock(int edge, int i) {
    int last = u_frame.tessellation.x - 1;
    return edge == 0 ? ivec2(0, i) : edge == 1 ? ivec2(i, 0) : edge == 2 ? ivec2(last, i)
                                                                         : ivec2(i, last);
}

// Ends of a block's edge in block corners, in the order of the domain coordinate that runs
// along it (u for north/south, v for west/east).
void terrainEdgeEnds(int edge, out ivec2 a, out ivec2 b) {
    a = edge == 2 ? ivec2(1, 0) : edge == 3 ? ivec2(0, 1) : ivec2(0, 0);
    b = (edge == 0 || edge == 2) ? a + ivec2(0, 1) : a + ivec2(1, 0);
}

#endif  // TERRAIN_PRIMITIVES_GLSL
