// Ripolles et al.: appends the family slots a step freed to the free-slot stack, above what
// the step left of it (ripolles_bookkeeping.comp, phase 1), and marks them free (pattern 0:
// the next step's family pass skips them). After the step, not in it: the freed family's
// other children still read it during the step.
#include "ripolles_tessellation.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = TERRAIN_BINDING_RIPOLLES_FREE_SLOTS) writeonly buffer FreeSlots {
    int u_freeSlots[];
};
layout(std430, binding = TERRAIN_BINDING_RIPOLLES_FREED_SLOTS) readonly buffer FreedSlots {
    int u_freedSlots[];
};

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= c_freedSlots) return;
    int slot = u_freedSlots[i];
    u_freeSlots[c_mergeBase + i] = slot;
    u_families[slot].pattern = 0;
}
