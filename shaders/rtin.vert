// RTIN yardstick draw (LodMethod::Rtin), vertex stage: the CPU-built mesh's vertices arrive
// as DEM samples relative to the camera's anchor sample (integers, exact in float), their
// height and their full-resolution normal, and are placed exactly as reference.vert places
// the reference's, so the two draws differ only where the mesh leaves samples out.
// reference.frag shades them.
#include "Bindings.h"
#include "terrain_frame.glsl"

layout(location = 0) in vec3 a_sampleHeight;  // DEM sample − anchor (x east, y south), height m
layout(location = 1) in vec3 a_normal;


layout(location = 0) out vec3 o_fromCameraM;
layout(location = 1) out vec3 o_normal;
layout(location = 2) out float o_heightM;
layout(location = 3) out vec2 o_demSample;

void main() {
    precise vec2 demSample = a_sampleHeight.xy;
    o_demSample = demSample;
    o_normal = a_normal;
    o_heightM = a_sampleHeight.z;
    precise vec2 metres = (demSample - u_frame.planeCamera.xy) * u_frame.planeSpacing.xy;
    precise float z = a_sampleHeight.z - u_frame.planeCamera.z;
    vec3 position = vec3(metres.x, -metres.y, z);  // rows run south: +row is −y
    o_fromCameraM = position;
    gl_Position = u_frame.viewProjection * vec4(position, 1.0);
}
