// The patch draws' per-instance records (PatchInstanceLayout.h, one per drawn patch, std430; the
// renderers write them through runtime/draw PatchInstance.h), and the primitives of an
// instance (terrain_primitives.glsl). Where a record's patch lies is its surface's:
// surface_plane.glsl, surface_globe.glsl.
#ifndef TERRAIN_PATCHES_GLSL
#define TERRAIN_PATCHES_GLSL

#include "Bindings.h"
#include "PatchInstanceLayout.h"
#include "terrain_primitives.glsl"

struct PatchInstance {
    TERRAIN_PATCH_INSTANCE_MEMBERS(TERRAIN_GLSL_VEC4, TERRAIN_GLSL_IVEC4)
};

layout(std430, binding = TERRAIN_BINDING_PATCH_INSTANCES) readonly buffer PatchInstances {
    PatchInstance u_instances[];
};

#endif  // TERRAIN_PATCHES_GLSL
