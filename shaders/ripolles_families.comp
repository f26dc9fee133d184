// Ripolles et al., the first pass of a tessellation step (§3.2), over the families: the
// count of leaf children at the step's start, and whether the parent's edges now select a
// different pattern (`wants` holds it + 8). Every live family is checked, also one whose
// children are all refined further (no leaf of it would see the change).
// ripolles_step.geom then steps every leaf.
#include "ripolles_tessellation.glsl"

layout(local_size_x = 64) in;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= c_familyBump) return;
    Family family = u_families[i];
    // Written here only, so that the step's leaves all read the same values while child 0
    // of a family rewrites its pattern and counts.
    u_families[i].allLeavesAtStart = family.leafChildren == kChildren[family.pattern] ? 1 : 0;
    u_families[i].wants = 0;
    if (family.pattern == 0) return;  // a free slot
    int pattern = refinementPattern(family.p0, family.p1, family.p2);
    if (pattern != family.pattern) u_families[i].wants = 8 | pattern;
}
