// Preview draw (terrain-render before the pyramid exists): one instance per patch of a
// regular grid over a single height texture; the vertex stage only places patch corners.
#include "Bindings.h"

uniform int u_patchesPerSide;  // the grid is square
uniform int u_patchQuads;    // quads along a patch side

layout(location = 0) out vec2 o_sample;  // corner position in samples (column, row)

void main() {
    ivec2 patchXY = ivec2(gl_InstanceID % u_patchesPerSide, gl_InstanceID / u_patchesPerSide);
    ivec2 corner = ivec2(gl_VertexID & 1, gl_VertexID >> 1);  // (0,0) (1,0) (0,1) (1,1)
    o_sample = vec2((patchXY + corner) * u_patchQuads);
}
