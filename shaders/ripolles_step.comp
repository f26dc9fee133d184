// Ripolles et al., one tessellation step (§3.2), built in two programs from this file:
//   RIPOLLES_FAMILIES  over the families: the count of leaf children at the step's start, and
//                      whether the parent's edges now select a different pattern (`wants`
//                      holds it + 8). Every live family is checked, also one whose children
//                      are all refined further (no leaf of it would see the change);
//   (otherwise)        over the leaves, the step itself: a leaf whose family, or a family above
//                      it, wants to change is coarsened — once all its siblings are leaves,
//                      child 0 recreates the parent (Eq. 3–6) and refines it again with the
//                      pattern its edges select now, or leaves it whole ("the most suitable
//                      pattern", §3.2); a family below one that changes is coarsened whole.
//                      Every other leaf is refined by the pattern of its edges (Eq. 1–2), or
//                      kept. One step changes the tessellation by at most one level: the
//                      coherence of §3.2, the previous tessellation reused.
// The CPU has made the lists large enough for the step's worst case beforehand.
#include "ripolles_tessellation.glsl"

layout(local_size_x = 64) in;

#ifdef RIPOLLES_FAMILIES
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
#else
layout(std430, binding = TERRAIN_BINDING_RIPOLLES_LEAVES) readonly buffer Current {
    Leaf u_leaves[];
};

layout(std430, binding = TERRAIN_BINDING_RIPOLLES_NEXT_LEAVES) writeonly buffer Next {
    Leaf u_next[];
};
// The free family slots of earlier steps (a stack: this step pops from the top) and the
// ones this step frees (merged into the stack after the step).
layout(std430, binding = TERRAIN_BINDING_RIPOLLES_FREE_SLOTS) readonly buffer FreeSlots {
    int u_freeSlots[];
};
layout(std430, binding = TERRAIN_BINDING_RIPOLLES_FREED_SLOTS) writeonly buffer FreedSlots {
    int u_freedSlots[];
};

void emit(vec2 a, vec2 b, vec2 c, int family, int childType) {
    u_next[atomicAdd(c_nextLeaves, 1u)] = Leaf(a, b, c, family, childType);
}

void emitChildren(vec2 v0, vec2 v1, vec2 v2, int pattern, int family) {
    for (int c = 0; c < kChildren[pattern]; ++c) {
        ivec3 k = kPattern[pattern][c];
        emit(corner(k.x, v0, v1, v2), corner(k.y, v0, v1, v2), corner(k.z, v0, v1, v2), family, c);
    }
}

int allocateFamily() {
    uint taken = atomicAdd(c_freeTaken, 1u);
    if (taken < c_freeSlots) return u_freeSlots[c_freeSlots - 1u - taken];
    return int(atomicAdd(c_familyBump, 1u));
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= c_leaves) return;
    Leaf t = u_leaves[i];
    int f = t.family;
    if (f >= 0) {
        bool forced = false;
        for (int a = u_families[f].parentFamily; a >= 0 && !forced; a = u_families[a].parentFamily) {
            forced = u_families[a].wants != 0;
        }
        Family family = u_families[f];
        if (forced || family.wants != 0) {
            if (family.allLeavesAtStart == 0) {
                emit(t.v0, t.v1, t.v2, f, t.childType);  // a sibling is still refined: wait
                return;
            }
            if (t.childType != 0) return;  // child 0 rebuilds the family
            atomicAdd(c_changes, 1u);
            int pattern = forced ? 0 : family.wants & 7;
            if (pattern == 0) {
                emit(family.p0, family.p1, family.p2, family.parentFamily, family.parentChildType);
                if (family.parentFamily >= 0) {
                    atomicAdd(u_families[family.parentFamily].leafChildren, 1);
                }
                u_freedSlots[atomicAdd(c_freedSlots, 1u)] = f;  // ripolles_merge.comp frees it
            } else {
                u_families[f].pattern = pattern;
                u_families[f].leafChildren = kChildren[pattern];
                emitChildren(family.p0, family.p1, family.p2, pattern, f);
            }
            return;
        }
    }
    int pattern = refinementPattern(t.v0, t.v1, t.v2);
    if (pattern == 0) {
        emit(t.v0, t.v1, t.v2, f, t.childType);
        return;
    }
    atomicAdd(c_changes, 1u);
    int g = allocateFamily();
    u_families[g] = Family(t.v0, t.v1, t.v2, f, t.childType, pattern, kChildren[pattern], 0, 0);
    if (f >= 0) atomicAdd(u_families[f].leafChildren, -1);
    emitChildren(t.v0, t.v1, t.v2, pattern, g);
}
#endif
