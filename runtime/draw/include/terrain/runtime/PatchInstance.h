// PatchInstance: one drawn patch as the GPU reads it, the C++ struct expanded from the member
// list the shaders expand too (shaders/PatchInstanceLayout.h, terrain_patches.glsl). The
// renderers write one per instance through SurfacePlacement::place.
#pragma once

#include "PatchInstanceLayout.h"

#include <array>
#include <cstdint>

namespace terrain::runtime {

#define TERRAIN_CPP_INSTANCE_VEC4(name) std::array<float, 4> name{};
#define TERRAIN_CPP_INSTANCE_IVEC4(name) std::array<std::int32_t, 4> name{};

/// std430: every member a vec4 or an ivec4.
struct alignas(16) PatchInstance {
    TERRAIN_PATCH_INSTANCE_MEMBERS(TERRAIN_CPP_INSTANCE_VEC4, TERRAIN_CPP_INSTANCE_IVEC4)
};
static_assert(sizeof(PatchInstance) == 11 * 16, "PatchInstance: std430 layout");

}  // namespace terrain::runtime
