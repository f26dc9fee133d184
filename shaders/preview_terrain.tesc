// Preview tessellation factors: each edge is cut so a segment spans about
// u_pixelsPerSegment pixels, from the edge's own ends only, so the two patches sharing an
// edge always agree (no cracks). Factors are powers of two so vertices land on samples.
// This is a stand-in: the error-driven rule of Yusov & Shevtsov §5 replaces it.
#include "Bindings.h"

layout(vertices = 4) out;

layout(binding = TERRAIN_BINDING_HEIGHTS) uniform sampler2D u_heights;
uniform vec3 u_cameraSample;     // camera position: x, z in samples, y in metres
uniform float u_sampleSpacingM;
uniform float u_gammaPx;         // viewport height / (2 tan(fovY / 2))
uniform float u_pixelsPerSegment;
uniform int u_patchQuads;

layout(location = 0) in vec2 i_sample[];
layout(location = 0) out vec2 o_sample[];

vec3 metresFromCamera(vec2 sampleXY) {
    float h = texelFetch(u_heights, ivec2(sampleXY), 0).r;
    return vec3((sampleXY.x - u_cameraSample.x) * u_sampleSpacingM, h - u_cameraSample.y,
                (sampleXY.y - u_cameraSample.z) * u_sampleSpacingM);
}

float edgeFactor(vec2 a, vec2 b) {
    vec3 pa = metresFromCamera(a), pb = metresFromCamera(b);
    float distanceM = max(length(0.5 * (pa + pb)), 1e-3);
    float projectedPx = u_gammaPx * length(pa - pb) / distanceM;
    float wanted = clamp(projectedPx / u_pixelsPerSegment, 1.0, float(u_patchQuads));
    return exp2(ceil(log2(wanted)));
}

void main() {
    o_sample[gl_InvocationID] = i_sample[gl_InvocationID];
    if (gl_InvocationID == 0) {
        // Quad domain edges: 0 is u = 0, 1 is v = 0, 2 is u = 1, 3 is v = 1.
        float left = edgeFactor(i_sample[0], i_sample[2]);
        float top = edgeFactor(i_sample[0], i_sample[1]);
        float right = edgeFactor(i_sample[1], i_sample[3]);
        float bottom = edgeFactor(i_sample[2], i_sample[3]);
        gl_TessLevelOuter[0] = left;
        gl_TessLevelOuter[1] = top;
        gl_TessLevelOuter[2] = right;
        gl_TessLevelOuter[3] = bottom;
        gl_TessLevelInner[0] = max(top, bottom);
        gl_TessLevelInner[1] = max(left, right);
    }
}
