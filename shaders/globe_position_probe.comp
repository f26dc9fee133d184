// Globe position probe, compute stage: evaluates globePositionM (surface_globe.glsl, the
// function globe.tese places every vertex with) for a list of (instance, patch sample,
// height) probes and writes the camera-relative positions back, so GlobePrecisionTest can
// hold the GPU's float arithmetic to a double-precision reference.
#include "Bindings.h"
#include "surface_globe.glsl"

uniform int u_patchQuads;  // N − 1

layout(local_size_x = 64) in;

struct Probe {
    vec4 sampleHeight;  // patch sample (x, y), height (z)
    ivec4 instance;     // x: the instance record
};
layout(std430, binding = 2) readonly buffer Probes { Probe u_probes[]; };
layout(std430, binding = 3) writeonly buffer Positions { vec4 u_positions[]; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= uint(u_probes.length())) return;
    Probe probe = u_probes[i];
    vec3 direction;
    precise vec2 uv = probe.sampleHeight.xy / float(u_patchQuads);
    vec3 position = globePositionM(u_instances[probe.instance.x], uv, probe.sampleHeight.z,
                                   direction);
    u_positions[i] = vec4(position, 0.0);
}
