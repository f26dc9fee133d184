// The per-frame parameters of the patch draws as the uniform block u_frame: the members of
// FrameBlockLayout.h, expanded into GLSL (runtime/draw FrameBlock.h expands the same list
// into the C++ struct the renderers upload).
#ifndef TERRAIN_FRAME_GLSL
#define TERRAIN_FRAME_GLSL

#include "Bindings.h"
#include "FrameBlockLayout.h"

#define TERRAIN_GLSL_MAT4(name) mat4 name;
#define TERRAIN_GLSL_VEC4(name) vec4 name;
#define TERRAIN_GLSL_IVEC4(name) ivec4 name;
#define TERRAIN_GLSL_VEC4_ARRAY(name, count) vec4 name[count];

layout(std140, binding = TERRAIN_BINDING_FRAME_BLOCK) uniform FrameBlock {
    TERRAIN_FRAME_BLOCK_MEMBERS(TERRAIN_GLSL_MAT4, TERRAIN_GLSL_VEC4, TERRAIN_GLSL_IVEC4,
                                TERRAIN_GLSL_VEC4_ARRAY)
} u_frame;

// The plane's anchor: the DEM sample at or before the camera, which positions are relative to
// (demExtent's first sample is minus it).
vec2 planeAnchorSample() { return -u_frame.demExtent.xy; }

#endif  // TERRAIN_FRAME_GLSL
