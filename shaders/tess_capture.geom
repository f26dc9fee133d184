// Tessellation capture, geometry stage: appends each triangle's three domain points to a
// buffer and draws nothing, so a test can read the tessellator's triangulation itself
// (which GL leaves to the implementation in the strips next to the outer edges).
#include "Bindings.h"

layout(triangles) in;
layout(points, max_vertices = 1) out;

layout(location = 0) in vec2 i_tessCoord[];

layout(std430, binding = 0) buffer CapturedTriangles {
    uint u_triangleCount;  // triangles generated, also past the capacity
    uint u_padding;
    vec2 u_domainPoints[];  // 3 per triangle
};

void main() {
    uint slot = atomicAdd(u_triangleCount, 1u);
    if (3u * slot + 2u < uint(u_domainPoints.length())) {
        for (uint i = 0u; i < 3u; ++i) u_domainPoints[3u * slot + i] = i_tessCoord[i];
    }
}
