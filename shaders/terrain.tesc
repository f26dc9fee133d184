// Terrain draw, tessellation control: one factor for every edge of every block.
// A uniform factor keeps shared edges identical, so there are no cracks inside a level.
#include "Bindings.h"

layout(vertices = 4) out;

uniform float u_tessFactor;  // segments per block edge, a power of two ≤ block quads

layout(location = 0) in vec2 i_sample[];
layout(location = 1) flat in int i_instance[];
layout(location = 0) out vec2 o_sample[];
layout(location = 1) flat out int o_instance[];

void main() {
    o_sample[gl_InvocationID] = i_sample[gl_InvocationID];
    o_instance[gl_InvocationID] = i_instance[gl_InvocationID];
    if (gl_InvocationID == 0) {
        gl_TessLevelOuter[0] = u_tessFactor;
        gl_TessLevelOuter[1] = u_tessFactor;
        gl_TessLevelOuter[2] = u_tessFactor;
        gl_TessLevelOuter[3] = u_tessFactor;
        gl_TessLevelInner[0] = u_tessFactor;
        gl_TessLevelInner[1] = u_tessFactor;
    }
}
