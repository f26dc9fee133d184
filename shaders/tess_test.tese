// Tessellation test, evaluation stage: bilinear placement of the domain point, and
// gl_TessCoord passed on so the fragment colour proves this stage ran.

layout(quads, equal_spacing, ccw) in;

layout(location = 0) in vec2 i_position[];
layout(location = 0) out vec2 o_tessCoord;

void main() {
    // Patch corners in (u, v) order: (0,0), (1,0), (1,1), (0,1).
    vec2 bottom = mix(i_position[0], i_position[1], gl_TessCoord.x);
    vec2 top = mix(i_position[3], i_position[2], gl_TessCoord.x);
    o_tessCoord = gl_TessCoord.xy;
    gl_Position = vec4(mix(bottom, top, gl_TessCoord.y), 0.0, 1.0);
}
