// Tessellation test, control stage: one quad patch with the levels given as uniforms, so
// the test can compare GL_PRIMITIVES_GENERATED with the CPU reference count.

layout(vertices = 4) out;

uniform vec4 u_outerLevels;  // left (u = 0), bottom (v = 0), right (u = 1), top (v = 1)
uniform vec2 u_innerLevels;

layout(location = 0) in vec2 i_position[];
layout(location = 0) out vec2 o_position[];

void main() {
    o_position[gl_InvocationID] = i_position[gl_InvocationID];
    if (gl_InvocationID == 0) {
        gl_TessLevelOuter[0] = u_outerLevels.x;
        gl_TessLevelOuter[1] = u_outerLevels.y;
        gl_TessLevelOuter[2] = u_outerLevels.z;
        gl_TessLevelOuter[3] = u_outerLevels.w;
        gl_TessLevelInner[0] = u_innerLevels.x;
        gl_TessLevelInner[1] = u_innerLevels.y;
    }
}
